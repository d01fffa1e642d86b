#include "yaml_convert.hpp"

#include <fmt/format.h>
#include <pybind11/numpy.h>

#include <cmath>
#include <regex>

namespace py = pybind11;

namespace velum::python {
namespace {

std::string number_text(double v) {
  if (std::isnan(v)) return ".nan";
  if (std::isinf(v)) return v > 0 ? ".inf" : "-.inf";
  return fmt::format("{}", v);  // shortest text that reads back to the same double
}

YAML::Node scalar(const std::string& text) {
  return YAML::Node(text);
}

[[noreturn]] void type_error(py::handle obj, const std::string& path) {
  throw py::type_error(
      fmt::format("{}: cannot write a {} into a model (use dicts, lists, "
                  "numbers, strings or numpy arrays)",
                  path.empty() ? "model" : path,
                  py::str(py::type::handle_of(obj).attr("__name__")).cast<std::string>()));
}

/// One axis of a C-contiguous numpy array, from element `offset` with `stride` per item.
template <class T>
YAML::Node array_node(const T* data, const std::vector<py::ssize_t>& shape, size_t axis,
                      py::ssize_t offset) {
  YAML::Node seq(YAML::NodeType::Sequence);
  py::ssize_t stride = 1;
  for (size_t a = axis + 1; a < shape.size(); ++a) stride *= shape[a];
  for (py::ssize_t i = 0; i < shape[axis]; ++i) {
    const py::ssize_t at = offset + i * stride;
    if (axis + 1 == shape.size()) {
      if constexpr (std::is_floating_point_v<T>)
        seq.push_back(scalar(number_text(data[at])));
      else if constexpr (std::is_same_v<T, bool>)
        seq.push_back(scalar(data[at] ? "true" : "false"));
      else
        seq.push_back(scalar(fmt::format("{}", data[at])));
    } else {
      seq.push_back(array_node(data, shape, axis + 1, at));
    }
  }
  return seq;
}

YAML::Node numpy_node(py::handle obj, const std::string& path) {
  const py::array a = py::reinterpret_borrow<py::array>(obj);
  if (a.ndim() == 0) return to_yaml(obj.attr("item")(), path);
  const char kind = a.dtype().kind();
  const std::vector<py::ssize_t> shape(a.shape(), a.shape() + a.ndim());
  if (kind == 'f') {
    const auto c = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(obj);
    return array_node(c.data(), shape, 0, 0);
  }
  if (kind == 'i' || kind == 'u') {
    const auto c = py::array_t<long long, py::array::c_style | py::array::forcecast>::ensure(obj);
    return array_node(c.data(), shape, 0, 0);
  }
  if (kind == 'b') {
    const auto c = py::array_t<bool, py::array::c_style | py::array::forcecast>::ensure(obj);
    return array_node(c.data(), shape, 0, 0);
  }
  // Strings or objects: item by item.
  YAML::Node seq(YAML::NodeType::Sequence);
  py::list items = obj.attr("tolist")();
  for (size_t i = 0; i < items.size(); ++i)
    seq.push_back(to_yaml(items[i], fmt::format("{}[{}]", path, i)));
  return seq;
}

bool is_plain_int(const std::string& s) {
  static const std::regex re("[-+]?[0-9]+");
  return std::regex_match(s, re);
}

bool is_plain_float(const std::string& s) {
  static const std::regex re(
      "[-+]?([0-9]+\\.?[0-9]*|\\.[0-9]+)([eE][-+]?[0-9]+)?|[-+]?\\.(inf|Inf|INF)|\\.(nan|NaN|NAN)");
  return std::regex_match(s, re);
}

}  // namespace

YAML::Node to_yaml(py::handle obj, const std::string& path) {
  if (obj.is_none()) return YAML::Node(YAML::NodeType::Null);
  if (PyBool_Check(obj.ptr())) return scalar(obj.ptr() == Py_True ? "true" : "false");
  if (PyLong_Check(obj.ptr())) {
    int overflow = 0;
    const long long v = PyLong_AsLongLongAndOverflow(obj.ptr(), &overflow);
    if (overflow != 0)
      throw py::value_error(fmt::format("{}: integer out of range", path.empty() ? "model" : path));
    return scalar(fmt::format("{}", v));
  }
  if (PyFloat_Check(obj.ptr())) return scalar(number_text(PyFloat_AsDouble(obj.ptr())));
  if (PyUnicode_Check(obj.ptr())) return scalar(obj.cast<std::string>());
  if (py::isinstance<py::array>(obj)) return numpy_node(obj, path);
  if (py::isinstance<py::list>(obj) || py::isinstance<py::tuple>(obj)) {
    YAML::Node seq(YAML::NodeType::Sequence);
    size_t i = 0;
    for (py::handle item : obj) seq.push_back(to_yaml(item, fmt::format("{}[{}]", path, i++)));
    return seq;
  }
  static const py::object mapping = py::module_::import("collections.abc").attr("Mapping");
  if (py::isinstance<py::dict>(obj) || py::isinstance(obj, mapping)) {
    YAML::Node map(YAML::NodeType::Map);
    for (py::handle key : obj) {
      if (!PyUnicode_Check(key.ptr())) type_error(key, path.empty() ? "a key" : path + " key");
      const std::string k = key.cast<std::string>();
      map[k] = to_yaml(obj[key], path.empty() ? k : path + "." + k);
    }
    return map;
  }
  if (py::hasattr(obj, "__fspath__"))
    return scalar(py::module_::import("os").attr("fspath")(obj).cast<std::string>());
  // numpy scalars (np.int64, np.float32, np.bool_) and anything else with item().
  if (py::hasattr(obj, "dtype") && py::hasattr(obj, "item"))
    return to_yaml(obj.attr("item")(), path);
  type_error(obj, path);
}

py::object from_yaml(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Undefined:
    case YAML::NodeType::Null:
      return py::none();
    case YAML::NodeType::Sequence: {
      py::list out;
      for (const auto& item : node) out.append(from_yaml(item));
      return out;
    }
    case YAML::NodeType::Map: {
      py::dict out;
      for (const auto& kv : node) out[from_yaml(kv.first)] = from_yaml(kv.second);
      return out;
    }
    case YAML::NodeType::Scalar:
      break;
  }
  const std::string& s = node.Scalar();
  if (node.Tag() == "!") return py::str(s);  // quoted: text, whatever it looks like
  if (s.empty() || s == "~" || s == "null" || s == "Null" || s == "NULL") return py::none();
  if (s == "true" || s == "True" || s == "TRUE") return py::bool_(true);
  if (s == "false" || s == "False" || s == "FALSE") return py::bool_(false);
  if (is_plain_int(s))
    return py::reinterpret_steal<py::object>(PyLong_FromString(s.c_str(), nullptr, 10));
  double v = 0;
  if (is_plain_float(s) && YAML::convert<double>::decode(node, v)) return py::float_(v);
  return py::str(s);
}

}  // namespace velum::python
