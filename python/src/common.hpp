#pragma once
// Shared by the two extension modules: numpy <-> Image, the error translation, and long calls that
// release the GIL and stop on Ctrl-C.
#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>

#include "hydrolux/core/error.hpp"
#include "hydrolux/core/image.hpp"
#include "hydrolux/core/progress.hpp"

namespace hydrolux::py_bind {

namespace py = pybind11;

// Thrown from a progress callback once Python asked to stop (Ctrl-C): unwinds the library's work.
struct Cancelled : std::exception {
  const char* what() const noexcept override { return "cancelled"; }
};

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
  throw Error(fmt::format("{} = {:g} is outside [{:g}, {:g}]{}", it->second.arg, e.value() * s, e.lo() * s, e.hi() * s,
                          e.context().empty() ? std::string() : ", the valid range of " + e.context()));
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

// ---- images ---------------------------------------------------------------------------------

using FloatArray = py::array_t<float, py::array::c_style | py::array::forcecast>;

// A numpy image (H, W) or (H, W, C), any real dtype, as a linear float Image (copied).
inline Image to_image(const py::array& any, const char* arg) {
  if (any.ndim() != 2 && any.ndim() != 3)
    throw Error(std::string(arg) + ": expected an array of shape (height, width) or (height, width, channels), got " +
                std::to_string(any.ndim()) + " dimensions");
  if (any.dtype().kind() == 'c' || any.dtype().kind() == 'O' || any.dtype().kind() == 'U' || any.dtype().kind() == 'S')
    throw Error(std::string(arg) + ": expected a real-valued array (float32 or float64), got dtype " +
                py::str(any.dtype()).cast<std::string>());
  const FloatArray a = FloatArray::ensure(any);
  const auto h = a.shape(0), w = a.shape(1), c = a.ndim() == 3 ? a.shape(2) : 1;
  if (h < 1 || w < 1 || c < 1 || h > 65536 || w > 65536 || c > 64)
    throw Error(std::string(arg) + ": shape (" + std::to_string(h) + ", " + std::to_string(w) + ", " + std::to_string(c) +
                ") is outside 1..65536 pixels a side and 1..64 channels");
  Image img(static_cast<int>(w), static_cast<int>(h), static_cast<int>(c));
  std::copy(a.data(), a.data() + a.size(), img.pixels.begin());
  return img;
}

// An Image as a new numpy float32 array (H, W, C).
inline py::array_t<float> to_array(const Image& img) {
  py::array_t<float> out({py::ssize_t(img.height), py::ssize_t(img.width), py::ssize_t(img.channels)});
  std::copy(img.pixels.begin(), img.pixels.end(), out.mutable_data());
  return out;
}

}  // namespace hydrolux::py_bind
