// plantnbv._plantnbv: the compiled part of the Python package (docs/python.md).

#include <Python.h>

#include <plantnbv/common/error.h>
#include <plantnbv/experiment/trial.h>

#include "bindings.h"

namespace plantnbv {
namespace python {

namespace py = pybind11;

void bindErrors(py::module_& m)
{
  // Python exceptions that are also the built-in ones a caller catches: a bad value is a
  // ValueError, a file problem an OSError (FileNotFoundError for a missing file).
  auto make = [&m](const char* name, py::handle bases, const char* doc) {
    const std::string qualified = std::string("plantnbv.") + name;
    PyObject* type =
        PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases.ptr(), nullptr);
    if (!type)
      throw py::error_already_set();
    py::object object = py::reinterpret_steal<py::object>(type);
    m.attr(name) = object;
    return object;
  };
  const py::object builtins = py::module_::import("builtins");
  const py::object error = make("Error", PyExc_Exception,
                                "Base of every error plantnbv raises on bad input or a "
                                "failed operation.");
  const py::object invalid =
      make("InvalidArgumentError", py::make_tuple(error, builtins.attr("ValueError")),
           "A value outside its domain (a ValueError).");
  const py::object format =
      make("FormatError", py::make_tuple(error, builtins.attr("ValueError")),
           "A file was read but its content is malformed (a ValueError).");
  const py::object io = make("IoError", py::make_tuple(error, builtins.attr("OSError")),
                             "A file could not be opened, read or written (an OSError).");
  const py::object not_found =
      make("FileNotFoundError", py::make_tuple(io, builtins.attr("FileNotFoundError")),
           "A file or folder to read does not exist (a FileNotFoundError).");
  const py::object time_limit =
      make("TimeLimitError", py::make_tuple(error, builtins.attr("TimeoutError")),
           "A trial ran past its time limit (a TimeoutError).");
  // Held for the interpreter's life, like the module.
  static PyObject* types[6];
  types[0] = error.ptr(), types[1] = invalid.ptr(), types[2] = format.ptr();
  types[3] = io.ptr(), types[4] = not_found.ptr(), types[5] = time_limit.ptr();
  for (PyObject* t : types)
    Py_INCREF(t);
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p)
        std::rethrow_exception(p);
    } catch (const FileNotFoundError& e) {
      PyErr_SetString(types[4], e.what());
    } catch (const IoError& e) {
      PyErr_SetString(types[3], e.what());
    } catch (const FormatError& e) {
      PyErr_SetString(types[2], e.what());
    } catch (const InvalidArgumentError& e) {
      PyErr_SetString(types[1], e.what());
    } catch (const TimeLimitError& e) {
      PyErr_SetString(types[5], e.what());
    } catch (const Error& e) {
      PyErr_SetString(types[0], e.what());
    }
  });
}

} // namespace python
} // namespace plantnbv

PYBIND11_MODULE(_plantnbv, m)
{
  using namespace plantnbv::python;
  m.doc() = "plantnbv: attention-driven next-best-view planning for plant reconstruction "
            "(the compiled module; import plantnbv).";
  bindErrors(m);
  bindGeometry(m);
  bindClouds(m);
  bindPlants(m);
  bindPlanning(m);
  bindExperiment(m);
}
