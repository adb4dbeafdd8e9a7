#pragma once
// Shared by the extension modules: numpy <-> Image, arguments checked and named, the error
// translation, and long calls that release the GIL and stop on Ctrl-C.
#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <complex>
#include <condition_variable>
#include <exception>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/image.hpp"
#include "hydrolux/core/progress.hpp"

namespace hydrolux::py_bind {

namespace py = pybind11;

// Thrown from a progress callback once Python asked to stop (Ctrl-C): unwinds the library's work.
struct Cancelled : std::exception {
  const char* what() const noexcept override { return "cancelled"; }
};

// A ValueError for a library error that names parameters (DomainError, ParamError), with what a door
// other than Python's keywords needs to say it in its own words, no text rewritten: `quantity`, the
// one refused (None for a ParamError), and `said(spellings)`, the message with each parameter spelled
// by the dict (the batch jobs' {"near_m": "--near-m", ...}; a name it lacks stays as it is).
template <class NamingError>
void set_value_error(const NamingError& e, const std::string& quantity) {
  py::object error = py::reinterpret_steal<py::object>(PyObject_CallFunction(PyExc_ValueError, "s", e.what()));
  if (!error) return;  // the call's own exception stands
  error.attr("quantity") = quantity.empty() ? py::object(py::none()) : py::object(py::str(quantity));
  error.attr("said") = py::cpp_function([e](const std::map<std::string, std::string>& spellings) {
    return e.said([&](std::string_view q) {
      const auto it = spellings.find(std::string(q));
      return it == spellings.end() ? std::string(q) : it->second;
    });
  });
  PyErr_SetObject(PyExc_ValueError, error.ptr());
}

// hydrolux's errors as Python's: a value out of range or an unknown name is a ValueError, a file
// problem an OSError (FileNotFoundError for a missing input).
inline void register_errors() {
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const Cancelled&) {
      PyErr_SetNone(PyExc_KeyboardInterrupt);
    } catch (const IoError& e) {
      const std::string what = e.what();
      PyErr_SetString(what.find("no such file") != std::string::npos || what.find("does not exist") != std::string::npos
                          ? PyExc_FileNotFoundError
                          : PyExc_OSError,
                      what.c_str());
    } catch (const IoFailure& e) {
      PyErr_SetString(PyExc_OSError, e.what());
    } catch (const DomainError& e) {
      set_value_error(e, e.quantity());
    } catch (const ParamError& e) {
      set_value_error(e, {});
    } catch (const Error& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
}

// A DomainError about a library quantity, said in the Python argument's name (e.g. "radius_m" of
// the drop camera is the caller's radius_mm, scaled): rethrows as Error with that name and range.
// Needs no GIL (it may run inside run_cancellable's worker).
struct ArgName {
  const char* arg;
  double scale = 1;  // value in the argument's unit = library value x scale
};
[[noreturn]] inline void rethrow_named(const DomainError& e, const std::map<std::string, ArgName>& names) {
  const auto it = names.find(e.quantity());
  if (it == names.end()) throw e;
  const double s = it->second.scale;
  throw Error(DomainError(it->second.arg, e.value() * s, e.lo() * s, e.hi() * s, e.context()).what());
}

// A ValueError naming the argument, its value and the valid range.
inline void require_arg(const char* arg, double value, double lo, double hi, const char* unit = "") {
  if (!(value >= lo && value <= hi))
    throw Error(fmt::format("{} = {:g} is outside [{:g}, {:g}]{}{}", arg, value, lo, hi, *unit ? " " : "", unit));
}

// Runs `work(progress)` on a thread of its own with the GIL released, while the calling thread
// wakes every 50 ms to let Python handle signals: on Ctrl-C the progress callback throws Cancelled
// inside the library (which unwinds and cleans up), and KeyboardInterrupt is raised here once the
// work has stopped. For calls long enough that a thread start (~20 us) does not matter.
template <class Work>
auto run_cancellable(Work&& work) -> std::invoke_result_t<Work&, const ProgressFn&> {
  using R = std::invoke_result_t<Work&, const ProgressFn&>;
  std::atomic<bool> cancel{false};
  const ProgressFn progress = [&cancel](double, std::string_view) {
    if (cancel.load(std::memory_order_relaxed)) throw Cancelled();
  };
  std::optional<R> result;
  std::exception_ptr failure;
  std::optional<py::error_already_set> interrupted;
  std::mutex m;
  std::condition_variable cv;
  bool done = false;
  {
    py::gil_scoped_release release;
    std::thread worker([&] {
      try {
        result.emplace(work(progress));
      } catch (...) {
        failure = std::current_exception();
      }
      std::lock_guard<std::mutex> lock(m);
      done = true;
      cv.notify_one();
    });
    std::unique_lock<std::mutex> lock(m);
    while (!done) {
      if (cv.wait_for(lock, std::chrono::milliseconds(50), [&] { return done; })) break;
      if (interrupted) continue;
      lock.unlock();
      {
        py::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() != 0) {
          interrupted.emplace();  // takes the pending KeyboardInterrupt (or what the handler raised)
          cancel = true;
        }
      }
      lock.lock();
    }
    lock.unlock();
    worker.join();
  }
  if (interrupted) throw std::move(*interrupted);
  if (failure) std::rethrow_exception(failure);
  return std::move(*result);
}

// ---- arguments ------------------------------------------------------------------------------

// A Python value as an error message may show it: short, and never an array's or a container's
// contents ("None", "'8x16'", "8.5", "an array of shape (3,) and dtype float64", "a list").
inline std::string describe(py::handle v) {
  if (v.is_none()) return "None";
  if (py::isinstance<py::array>(v)) {
    const auto a = py::reinterpret_borrow<py::array>(v);
    std::string shape;
    for (py::ssize_t i = 0; i < a.ndim(); ++i) shape += (i ? ", " : "") + std::to_string(a.shape(i));
    if (a.ndim() == 1) shape += ",";
    return fmt::format("an array of shape ({}) and dtype {}", shape, py::str(a.dtype()).cast<std::string>());
  }
  if (PyLong_Check(v.ptr())) {
    // A whole number of any size; its digits while they fit a line (str() refuses past 4300).
    const auto bits = v.attr("bit_length")().cast<long long>();
    if (bits > 128) return fmt::format("a whole number of {} digits", (long long)(double(bits) * 0.30103) + 1);
  }
  const bool text = PyUnicode_Check(v.ptr()) || PyBytes_Check(v.ptr());
  const bool number = PyLong_Check(v.ptr()) || PyFloat_Check(v.ptr()) || PyComplex_Check(v.ptr()) ||
                      py::isinstance(v, py::module_::import("numpy").attr("generic"));
  if (text || number) {
    std::string r = text ? py::repr(v).cast<std::string>() : py::str(v).cast<std::string>();
    if (r.size() > 40) r = r.substr(0, 37) + "...";
    return r;
  }
  return "a " + py::str(v.get_type().attr("__name__")).cast<std::string>();
}

inline bool is_bool(py::handle v) {
  return PyBool_Check(v.ptr()) || py::isinstance(v, py::module_::import("numpy").attr("bool_"));
}

// A whole-number argument (int, numpy integer, or a float with no fraction) in [lo, hi], as the
// CLI's integer flags take it and in the same words: "seed: 18446744073709551616 is outside the
// valid range [0, 9007199254740992]", "size: 8.5 is not a whole number; valid range [8, 16384] px"
// (ValueError). A bool, a string, None or an array is a TypeError naming the argument. No value,
// however large, reaches a C++ integer unchecked.
inline long long whole_arg(py::handle v, const char* arg, long long lo, long long hi, const char* unit = "") {
  const std::string range = fmt::format("[{}, {}]{}{}", lo, hi, *unit ? " " : "", unit);
  const bool array = py::isinstance<py::array>(v);  // ndarray has __index__ (for 0-d integer arrays)
  if (!array && !is_bool(v) && PyIndex_Check(v.ptr())) {
    const auto i = py::reinterpret_steal<py::object>(PyNumber_Index(v.ptr()));
    if (!i) throw py::error_already_set();
    int overflow = 0;
    const long long x = PyLong_AsLongLongAndOverflow(i.ptr(), &overflow);
    if (overflow == 0 && x == -1 && PyErr_Occurred()) throw py::error_already_set();
    if (overflow != 0 || x < lo || x > hi)
      throw Error(fmt::format("{}: {} is outside the valid range {}", arg, describe(i), range));
    return x;
  }
  if (!array && (PyFloat_Check(v.ptr()) || py::isinstance(v, py::module_::import("numpy").attr("floating")))) {
    const double d = PyFloat_AsDouble(v.ptr());
    if (d == -1.0 && PyErr_Occurred()) throw py::error_already_set();
    if (!std::isfinite(d) || d != std::floor(d))
      throw Error(fmt::format("{}: {} is not a whole number; valid range {}", arg, describe(v), range));
    if (d < double(lo) || d > double(hi))
      throw Error(fmt::format("{}: {} is outside the valid range {}", arg, describe(v), range));
    return static_cast<long long>(d);
  }
  throw py::type_error(fmt::format("{}: expected a whole number in {}, got {}", arg, range, describe(v)));
}

// A real-number argument (int, float, numpy number; not a bool): its value, +-inf past a double's
// range (so that the range check that follows names it). Anything else is a TypeError naming it.
inline double real_arg(py::handle v, const char* arg) {
  if (!py::isinstance<py::array>(v) && !is_bool(v) &&
      (PyFloat_Check(v.ptr()) || PyLong_Check(v.ptr()) ||
       py::isinstance(v, py::module_::import("numpy").attr("integer")) ||
       py::isinstance(v, py::module_::import("numpy").attr("floating")))) {
    const double d = PyFloat_AsDouble(v.ptr());
    if (d == -1.0 && PyErr_Occurred()) {
      if (!PyErr_ExceptionMatches(PyExc_OverflowError)) throw py::error_already_set();
      PyErr_Clear();
      return v.attr("__gt__")(0).cast<bool>() ? HUGE_VAL : -HUGE_VAL;
    }
    return d;
  }
  throw py::type_error(fmt::format("{}: expected a number, got {}", arg, describe(v)));
}

// A True/False argument (bool or numpy.bool_); anything else is a TypeError naming it.
inline bool flag_arg(py::handle v, const char* arg) {
  if (!is_bool(v)) throw py::type_error(fmt::format("{}: expected True or False, got {}", arg, describe(v)));
  return PyObject_IsTrue(v.ptr()) == 1;
}

// ---- arrays -----------------------------------------------------------------------------------

template <class T>
using CArray = py::array_t<T, py::array::c_style | py::array::forcecast>;
using FloatArray = CArray<float>;
using DoubleArray = CArray<double>;
using ComplexArray = py::array_t<std::complex<double>>;

inline std::vector<py::ssize_t> shape_of(const py::array& a) { return {a.shape(), a.shape() + a.ndim()}; }

// obj as a C-contiguous array of T, copied (converted) when it is not one already. Not
// array_t::ensure, which returns a null array and drops Python's error when the copy fails (the
// caller then reads through a null pointer): a copy that cannot be allocated raises MemoryError
// here. A value numpy cannot read as numbers is a TypeError naming `arg`, never its contents.
template <class T>
CArray<T> c_array(py::handle obj, const char* arg) {
  if (py::isinstance<py::array>(obj)) {
    const char kind = py::reinterpret_borrow<py::array>(obj).dtype().kind();
    const bool complex_ok = std::is_same_v<T, std::complex<double>> || std::is_same_v<T, std::complex<float>>;
    if (!(kind == 'b' || kind == 'i' || kind == 'u' || kind == 'f' || (complex_ok && kind == 'c')))
      throw py::type_error(fmt::format("{}: expected {} numbers, got {}", arg, complex_ok ? "complex" : "real",
                                       describe(obj)));
  }
  try {
    return CArray<T>(py::reinterpret_borrow<py::object>(obj));  // throws error_already_set, MemoryError kept
  } catch (py::error_already_set& e) {
    if (e.matches(PyExc_MemoryError)) throw;
    throw py::type_error(fmt::format("{}: expected numbers (one or an array), got {}", arg, describe(obj)));
  }
}

// A numpy image (H, W) or (H, W, C), any real dtype (bool, integers, floats) and any strides
// (a broadcast view too), as a linear float Image: the shape checked before anything is allocated,
// then one allocation (the Image's, std::bad_alloc -> MemoryError) that numpy casts into directly.
inline Image to_image(const py::array& any, const char* arg) {
  if (any.ndim() != 2 && any.ndim() != 3)
    throw Error(fmt::format("{}: expected an array of shape (height, width) or (height, width, channels), got {}",
                            arg, describe(any)));
  const char kind = any.dtype().kind();
  if (kind != 'b' && kind != 'i' && kind != 'u' && kind != 'f')
    throw Error(fmt::format("{}: expected a real-valued array (float32 or float64), got {}", arg, describe(any)));
  const auto h = any.shape(0), w = any.shape(1), c = any.ndim() == 3 ? any.shape(2) : 1;
  if (h < 1 || w < 1 || c < 1 || h > 65536 || w > 65536 || c > 64)
    throw Error(fmt::format("{}: shape ({}, {}, {}) is outside 1..65536 pixels a side and 1..64 channels", arg, h, w,
                            c));
  Image img(static_cast<int>(w), static_cast<int>(h), static_cast<int>(c));
  std::vector<py::ssize_t> shape{h, w};
  if (any.ndim() == 3) shape.push_back(c);
  // A view of the Image's pixels (the capsule only marks it as borrowed: the Image outlives it).
  py::array_t<float> view(shape, img.pixels.data(), py::capsule(img.pixels.data(), [](void*) {}));
  py::module_::import("numpy").attr("copyto")(view, any, py::arg("casting") = "unsafe");
  return img;
}

// An Image as a new numpy float32 array (H, W, C).
inline py::array_t<float> to_array(const Image& img) {
  py::array_t<float> out({py::ssize_t(img.height), py::ssize_t(img.width), py::ssize_t(img.channels)});
  std::copy(img.pixels.begin(), img.pixels.end(), out.mutable_data());
  return out;
}

}  // namespace hydrolux::py_bind
