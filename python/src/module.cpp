// velum._velum: the compiled half of the Python module. It reads a model dict through the same
// reader as `velum run` (dict -> YAML node -> ModelInput) and runs it in-process through
// run::run_model, the command line's own run, with the GIL released while it solves. The
// Python half (velum/*.py) wraps what these functions return into Model and Results objects.
#include <malloc.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <fmt/format.h>

#include <exception>
#include <map>

#include "velum/assembly/dof_map.hpp"
#include "velum/config.hpp"
#include "velum/io/model_reader_yaml.hpp"
#include "velum/run/run_model.hpp"
#include "yaml_convert.hpp"

namespace py = pybind11;

namespace velum::python {
namespace {

/// Raises velum.InputError (defined in velum/errors.py) with every message.
[[noreturn]] void raise_input_error(const std::vector<std::string>& messages) {
  const py::object cls = py::module_::import("velum.errors").attr("InputError");
  const py::object exc = cls(py::cast(messages));
  PyErr_SetObject(cls.ptr(), exc.ptr());
  throw py::error_already_set();
}

template <class T>
py::array_t<long long> id_array(const std::vector<T>& ids) {
  py::array_t<long long> out(static_cast<py::ssize_t>(ids.size()));
  auto w = out.mutable_unchecked<1>();
  for (size_t i = 0; i < ids.size(); ++i) w(static_cast<py::ssize_t>(i)) = ids[i];
  return out;
}

io::ModelSource source_of(const std::string& name, const std::string& base_dir) {
  io::ModelSource s;
  s.name = name;
  s.base_dir = base_dir;
  return s;
}

/// Reads a model given as Python objects; InputError becomes velum.InputError.
io::ModelInput read(py::handle model, const io::ModelSource& source) {
  YAML::Node root;
  try {
    root = to_yaml(model, "");
  } catch (const io::InputError& e) {  // too deep, holding itself, too large: as from a file
    std::vector<std::string> messages;
    for (const auto& m : e.messages()) messages.push_back(source.name + ": " + m);
    raise_input_error(messages);
  }
  try {
    py::gil_scoped_release nogil;
    return io::read_model(root, source);
  } catch (const io::InputError& e) {
    raise_input_error(e.messages());
  }
}

py::list blocks_of(const io::ModelInput& in) {
  py::list blocks;
  for (size_t b = 0; b < in.model.blocks.size(); ++b) {
    py::dict d;
    d["set"] = in.model.blocks[b]->set_name();
    d["type"] = std::string(in.model.blocks[b]->type_name());
    d["ids"] = id_array(in.element_ids[b]);
    blocks.append(std::move(d));
  }
  return blocks;
}

py::object read_yaml_file(const std::string& path) {
  // As `velum run` loads it: no FIFO or device, one document, no key twice, not too deep.
  YAML::Node root;
  try {
    py::gil_scoped_release nogil;
    root = io::load_model_yaml(path);
  } catch (const io::InputError& e) {
    raise_input_error(e.messages());
  }
  return from_yaml(root);
}

py::dict check(py::handle model, const std::string& name, const std::string& base_dir) {
  const io::ModelInput in = read(model, source_of(name, base_dir));
  int dofs = 0;
  try {
    dofs = DofMap(in.model).num_equations();
  } catch (const std::exception& e) {
    raise_input_error({fmt::format("{}: {}", name, e.what())});
  }
  py::dict out;
  out["title"] = in.title;
  out["nodes"] = in.model.num_nodes();
  out["elements"] = in.model.num_elements();
  out["dofs"] = dofs;
  out["blocks"] = blocks_of(in);
  py::dict materials;
  for (const auto& m : in.materials) materials[py::str(m.name)] = m.type;
  out["materials"] = materials;
  out["warnings"] = in.warnings;
  out["node_ids"] = id_array(in.model.node_ids);
  return out;
}

py::dict run(py::handle model, const std::string& name, const std::string& base_dir,
             std::optional<std::string> output, int threads, bool quiet, py::object progress) {
  velum::run::RunControls controls;  // starts the clock, as the command line does before it reads
  // As app/main.cpp: the factorisations allocate and free large blocks at every Newton
  // iteration; keep them in the heap instead of fresh zeroed pages from mmap each time.
  static const bool heap_tuned = [] {
    mallopt(M_MMAP_MAX, 0);
    mallopt(M_TRIM_THRESHOLD, 1 << 30);
    return true;
  }();
  (void)heap_tuned;
  io::ModelInput in = read(model, source_of(name, base_dir));
  if (output) controls.output = *output;
  controls.threads = threads;
  controls.quiet = quiet;
  // Each step: Ctrl-C, then the caller's progress(time, step, iterations); an explicit False
  // from it stops the run. A Python exception stops it too and is raised once the summary
  // is written.
  std::exception_ptr raised;
  controls.on_step = [&](const AcceptedStep& s) -> bool {
    py::gil_scoped_acquire gil;
    try {
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      if (progress.is_none()) return true;
      const py::object r = progress(s.t, s.step, s.iterations);
      return r.ptr() != Py_False;
    } catch (const py::error_already_set&) {
      raised = std::current_exception();
      return false;
    }
  };
  velum::run::RunOutcome outcome;
  {
    py::gil_scoped_release nogil;
    outcome = velum::run::run_model(in, controls);
  }
  controls.on_step = nullptr;
  if (raised) std::rethrow_exception(raised);

  py::dict out;
  out["status"] = outcome.status;
  out["errors"] = outcome.errors;
  out["directory"] = outcome.directory.string();
  out["stopped"] = outcome.stopped;
  out["warnings"] = in.warnings;
  out["node_ids"] = id_array(in.model.node_ids);
  out["blocks"] = blocks_of(in);
  return out;
}

}  // namespace
}  // namespace velum::python

PYBIND11_MODULE(_velum, m) {
  using namespace velum::python;
  m.doc() = "Velum's compiled core; use the velum package, not this module.";
  m.attr("__version__") = VELUM_VERSION;
  m.attr("EXIT_OK") = velum::run::kExitOk;
  m.attr("EXIT_BAD_INPUT") = velum::run::kExitBadInput;
  m.attr("EXIT_SOLVE_FAILED") = velum::run::kExitSolveFailed;
  m.attr("EXIT_IO") = velum::run::kExitIo;
  m.def("read_yaml", &read_yaml_file, py::arg("path"),
        "A YAML file as plain Python objects (no validation).");
  m.def("check", &check, py::arg("model"), py::arg("name"), py::arg("base_dir"),
        "Validates a model dict; its statistics, or velum.InputError.");
  m.def("run", &run, py::arg("model"), py::arg("name"), py::arg("base_dir"), py::arg("output"),
        py::arg("threads"), py::arg("quiet"), py::arg("progress"),
        "Runs a model dict in-process as `velum run` does; the outcome as a dict.");
}
