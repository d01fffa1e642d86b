#include "yaml_convert.hpp"

#include <fmt/format.h>
#include <pybind11/numpy.h>

#include <cmath>
#include <map>
#include <regex>
#include <unordered_set>

#include "velum/io/model_reader.hpp"

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

/// The name messages give a value at `path`.
std::string where(const std::string& path) {
  return path.empty() ? "model" : path;
}

/// A model too deep or holding itself: bad input, as the reader would say of the same YAML.
[[noreturn]] void structure_error(const std::string& path, const std::string& text) {
  throw io::InputError({fmt::format("{}: {}", where(path), text)});
}

/// A C-contiguous copy of `obj` as T; a copy numpy cannot make (out of memory) raises.
template <class T>
py::array_t<T, py::array::c_style | py::array::forcecast> contiguous(py::handle obj) {
  auto c = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(obj);
  if (!c) throw py::error_already_set();
  return c;
}

class ToYaml {
 public:
  YAML::Node convert(py::handle obj, const std::string& path, int depth) {
    if (obj.is_none()) return YAML::Node(YAML::NodeType::Null);
    const bool simple = obj.is_none() || PyBool_Check(obj.ptr()) || PyLong_Check(obj.ptr()) ||
                        PyFloat_Check(obj.ptr()) || PyUnicode_Check(obj.ptr());
    if (simple) count(1, path);
    if (obj.is_none()) return YAML::Node(YAML::NodeType::Null);
    if (PyBool_Check(obj.ptr())) return scalar(obj.ptr() == Py_True ? "true" : "false");
    if (PyLong_Check(obj.ptr())) {
      int overflow = 0;
      const long long v = PyLong_AsLongLongAndOverflow(obj.ptr(), &overflow);
      if (overflow != 0)
        throw py::value_error(fmt::format("{}: integer out of range", where(path)));
      return scalar(fmt::format("{}", v));
    }
    if (PyFloat_Check(obj.ptr())) return scalar(number_text(PyFloat_AsDouble(obj.ptr())));
    if (PyUnicode_Check(obj.ptr())) return scalar(obj.cast<std::string>());
    const bool array = py::isinstance<py::array>(obj);
    static const py::object mapping = py::module_::import("collections.abc").attr("Mapping");
    const bool map = !array && (py::isinstance<py::dict>(obj) || py::isinstance(obj, mapping));
    const bool seq =
        !array && !map && (py::isinstance<py::list>(obj) || py::isinstance<py::tuple>(obj));
    if (!array && !map && !seq) return leaf(obj, path, depth);
    // A container: at most kMaxYamlDepth deep (the reader's limit for a file), and never inside
    // itself (which would recurse without end).
    if (depth >= io::kMaxYamlDepth)
      structure_error(path, fmt::format("nested more than {} levels deep", io::kMaxYamlDepth));
    if (!open_.insert(obj.ptr()).second)
      structure_error(path, "contains itself (a dict or list that holds itself is no model)");
    // A container met again (the same list in two places, a Python alias bomb) is converted once
    // and shared, as a YAML alias is; what it stands for still counts at every use.
    if (auto it = done_.find(obj.ptr()); it != done_.end()) {
      open_.erase(obj.ptr());
      count(it->second.second, path);
      return it->second.first;
    }
    const std::uintmax_t before = values_;
    YAML::Node out = container(obj, path, depth, array, seq);
    open_.erase(obj.ptr());
    done_.emplace(obj.ptr(), std::make_pair(out, values_ - before));
    keep_.push_back(py::reinterpret_borrow<py::object>(obj));  // its address stays its own
    return out;
  }

 private:
  YAML::Node container(py::handle obj, const std::string& path, int depth, bool array, bool seq) {
    if (array) return numpy_node(obj, path, depth);
    if (seq) {
      YAML::Node out(YAML::NodeType::Sequence);
      size_t i = 0;
      for (py::handle item : obj)
        out.push_back(convert(item, fmt::format("{}[{}]", path, i++), depth + 1));
      count(1, path);
      return out;
    }
    YAML::Node out(YAML::NodeType::Map);
    for (py::handle key : obj) {
      if (!PyUnicode_Check(key.ptr())) type_error(key, path.empty() ? "a key" : path + " key");
      const std::string k = key.cast<std::string>();
      out[k] = convert(obj[key], path.empty() ? k : path + "." + k, depth + 1);
    }
    count(1, path);
    return out;
  }

  /// Counts `n` more values; the model as a whole may hold no more than a model file could.
  void count(std::uintmax_t n, const std::string& path) {
    values_ += n;
    if (values_ > kMaxValues)
      structure_error(path, fmt::format("the model holds more than {} values (each use of a shared "
                                        "list or dict counts), more than a model file of {} MiB "
                                        "can hold (put large meshes in a Gmsh file: mesh.file)",
                                        kMaxValues, io::kMaxModelFileBytes >> 20));
  }

  YAML::Node leaf(py::handle obj, const std::string& path, int depth) {
    count(1, path);
    if (py::hasattr(obj, "__fspath__"))
      return scalar(py::module_::import("os").attr("fspath")(obj).cast<std::string>());
    // numpy scalars (np.int64, np.float32, np.bool_) and anything else with item().
    if (py::hasattr(obj, "dtype") && py::hasattr(obj, "item")) {
      const py::object item = obj.attr("item")();
      if (item.ptr() != obj.ptr()) return convert(item, path, depth);
    }
    type_error(obj, path);
  }

  YAML::Node numpy_node(py::handle obj, const std::string& path, int depth) {
    const py::array a = py::reinterpret_borrow<py::array>(obj);
    if (a.ndim() == 0) return leaf(obj, path, depth);
    if (a.ndim() + depth > io::kMaxYamlDepth)
      structure_error(path, fmt::format("nested more than {} levels deep", io::kMaxYamlDepth));
    // A view may stand for far more items than memory holds (np.broadcast_to(0.0, (10**12,))):
    // each item becomes a YAML scalar, so an array a model file could not hold is refused
    // before it is copied.
    const auto items = static_cast<std::uintmax_t>(a.size());
    if (items > kMaxValues)
      structure_error(path, fmt::format("an array of {} items, more than a model file of {} MiB "
                                        "can hold (put large meshes in a Gmsh file: mesh.file)",
                                        items, io::kMaxModelFileBytes >> 20));
    count(items, path);
    const char kind = a.dtype().kind();
    const std::vector<py::ssize_t> shape(a.shape(), a.shape() + a.ndim());
    if (kind == 'f') return array_node(contiguous<double>(obj).data(), shape, 0, 0);
    if (kind == 'i' || kind == 'u')
      return array_node(contiguous<long long>(obj).data(), shape, 0, 0);
    if (kind == 'b') return array_node(contiguous<bool>(obj).data(), shape, 0, 0);
    // Strings or objects: item by item.
    YAML::Node seq(YAML::NodeType::Sequence);
    py::list items_list = obj.attr("tolist")();
    for (size_t i = 0; i < items_list.size(); ++i)
      seq.push_back(convert(items_list[i], fmt::format("{}[{}]", path, i), depth + 1));
    return seq;
  }

  /// Values (scalars, lists, maps) a model file could hold at most: two bytes each ("0,").
  static constexpr std::uintmax_t kMaxValues = io::kMaxModelFileBytes / 2;

  std::unordered_set<PyObject*> open_;  ///< the containers being converted (the path down)
  std::map<PyObject*, std::pair<YAML::Node, std::uintmax_t>> done_;  ///< node, values in it
  std::vector<py::object> keep_;  ///< the converted containers, alive while their address is a key
  std::uintmax_t values_ = 0;
};

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
  return ToYaml().convert(obj, path, 0);
}

namespace {

/// A scalar as Python: None, bool, int, float or str (quoted: str, whatever it looks like).
py::object scalar_value(const YAML::Node& node) {
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

/// YAML -> Python with every node converted once: an alias becomes the same Python object as
/// its anchor (as PyYAML does), so an alias bomb costs no more than its text.
class FromYaml {
 public:
  py::object convert(const YAML::Node& node) {
    const bool container = node.IsMap() || node.IsSequence();
    if (container && !node.Mark().is_null())
      if (auto it = done_.find(node.Mark().pos); it != done_.end()) return it->second;
    py::object out = convert_new(node);
    if (container && !node.Mark().is_null()) done_.emplace(node.Mark().pos, out);
    return out;
  }

 private:
  py::object convert_new(const YAML::Node& node) {
    switch (node.Type()) {
      case YAML::NodeType::Undefined:
      case YAML::NodeType::Null:
        return py::none();
      case YAML::NodeType::Sequence: {
        py::list out;
        for (const auto& item : node) out.append(convert(item));
        return out;
      }
      case YAML::NodeType::Map: {
        py::dict out;
        for (const auto& kv : node) out[convert(kv.first)] = convert(kv.second);
        return out;
      }
      case YAML::NodeType::Scalar:
        break;
    }
    return scalar_value(node);
  }

  std::map<std::size_t, py::object> done_;
};

}  // namespace

py::object from_yaml(const YAML::Node& node) {
  return FromYaml().convert(node);
}

}  // namespace velum::python
