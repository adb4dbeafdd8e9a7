// oneTBB for the hydrolux executable, loaded on first use (issue 24: the CLI's start-up).
//
// The library's parallel loops call oneTBB's runtime entry points (tbb::detail::r1::*, in
// libtbb.so.12); TBB's headers hold everything else. Linked with libtbb.so, every start of the CLI
// would load it and, through it, the shared libstdc++, which the executable otherwise has inside
// (-static-libstdc++, tools/hydrolux/CMakeLists.txt). This file defines those entry points in the
// executable itself, so the linker satisfies the library's references here and drops libtbb.so
// (--as-needed); each one loads libtbb.so.12 with dlopen on the first call and forwards to the real
// function, with the same arguments. Once loaded, oneTBB runs on the shared libstdc++ beside the
// executable's own: its exceptions (and those it carries from a loop body to the caller) cross
// between the two as they cross the plugins' boundary (tools/hydrolux/CMakeLists.txt).
//
// One entry point answers without loading: tbb::this_task_arena::max_concurrency() outside any
// arena, which the Mie amplitudes ask before deciding that a small job runs on the calling thread.
// Before oneTBB is loaded no thread can be inside an arena, so the answer is oneTBB's default
// concurrency, computed here as oneTBB 2021 computes it (src/tbb/misc_ex.cpp,
// initialize_hardware_concurrency_info: the CPUs in the process's affinity mask, at most the online
// CPUs, at least 1). Once libtbb is in the process (loaded here, or by a plugin's libraries), oneTBB
// answers itself.
//
// Only the executable links this (an object file, so its definitions come before every library on
// the link line); tests and the Python module link libtbb.so as before. An entry point the library
// starts to use that is not here is resolved from libtbb.so by the linker, which then loads it at
// start-up again: correct, only slower (scripts/bench-startup shows it; `readelf -d` lists libtbb).
#include <dlfcn.h>
#include <link.h>
#include <sched.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <climits>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <oneapi/tbb/cache_aligned_allocator.h>
#include <oneapi/tbb/detail/_exception.h>
#include <oneapi/tbb/detail/_small_object_pool.h>
#include <oneapi/tbb/detail/_task.h>
#include <oneapi/tbb/task_arena.h>
#include <oneapi/tbb/task_group.h>
#include <oneapi/tbb/tbb_allocator.h>

namespace {

constexpr const char* kTbbLibrary = "libtbb.so.12";

// The forwarded entry points: their index in kEntryNames is the first argument of HX_TBB_FORWARD.
constexpr const char* kEntryNames[] = {
    "_ZN3tbb6detail2r15spawnERNS0_2d14taskERNS2_18task_group_contextE",                              // 0
    "_ZN3tbb6detail2r15spawnERNS0_2d14taskERNS2_18task_group_contextEt",                             // 1
    "_ZN3tbb6detail2r116execute_and_waitERNS0_2d14taskERNS2_18task_group_contextERNS2_12wait_contextES6_",  // 2
    "_ZN3tbb6detail2r14waitERNS0_2d112wait_contextERNS2_18task_group_contextE",                      // 3
    "_ZN3tbb6detail2r114execution_slotEPKNS0_2d114execution_dataE",                                  // 4
    "_ZN3tbb6detail2r115current_contextEv",                                                          // 5
    "_ZN3tbb6detail2r114notify_waitersEm",                                                           // 6
    "_ZN3tbb6detail2r18allocateERPNS0_2d117small_object_poolEmRKNS2_14execution_dataE",              // 7
    "_ZN3tbb6detail2r18allocateERPNS0_2d117small_object_poolEm",                                     // 8
    "_ZN3tbb6detail2r110deallocateERNS0_2d117small_object_poolEPvmRKNS2_14execution_dataE",          // 9
    "_ZN3tbb6detail2r110deallocateERNS0_2d117small_object_poolEPvm",                                 // 10
    "_ZN3tbb6detail2r122cache_aligned_allocateEm",                                                   // 11
    "_ZN3tbb6detail2r124cache_aligned_deallocateEPv",                                                // 12
    "_ZN3tbb6detail2r115cache_line_sizeEv",                                                          // 13
    "_ZN3tbb6detail2r115allocate_memoryEm",                                                          // 14
    "_ZN3tbb6detail2r117deallocate_memoryEPv",                                                       // 15
    "_ZN3tbb6detail2r115throw_exceptionENS0_2d012exception_idE",                                     // 16
    "_ZN3tbb6detail2r110initializeERNS0_2d115task_arena_baseE",                                      // 17
    "_ZN3tbb6detail2r19terminateERNS0_2d115task_arena_baseE",                                        // 18
    "_ZN3tbb6detail2r16attachERNS0_2d115task_arena_baseE",                                           // 19
    "_ZN3tbb6detail2r17executeERNS0_2d115task_arena_baseERNS2_13delegate_baseE",                     // 20
    "_ZN3tbb6detail2r14waitERNS0_2d115task_arena_baseE",                                             // 21
    "_ZN3tbb6detail2r115max_concurrencyEPKNS0_2d115task_arena_baseE",                                // 22
    "_ZN3tbb6detail2r120isolate_within_arenaERNS0_2d113delegate_baseEl",                             // 23
    "_ZN3tbb6detail2r17enqueueERNS0_2d14taskEPNS2_15task_arena_baseE",                               // 24
    "_ZN3tbb6detail2r17enqueueERNS0_2d14taskERNS2_18task_group_contextEPNS2_15task_arena_baseE",     // 25
    "_ZN3tbb6detail2r110initializeERNS0_2d118task_group_contextE",                                   // 26
    "_ZN3tbb6detail2r17destroyERNS0_2d118task_group_contextE",                                       // 27
    "_ZN3tbb6detail2r15resetERNS0_2d118task_group_contextE",                                         // 28
    "_ZN3tbb6detail2r122cancel_group_executionERNS0_2d118task_group_contextE",                       // 29
    "_ZN3tbb6detail2r128is_group_execution_cancelledERNS0_2d118task_group_contextE",                 // 30
    "_ZN3tbb6detail2r119capture_fp_settingsERNS0_2d118task_group_contextE",                          // 31
};
constexpr std::size_t kEntries = sizeof(kEntryNames) / sizeof(kEntryNames[0]);

std::atomic<bool> g_loaded{false};

struct Entries {
  void* fn[kEntries] = {};
};

// libtbb.so.12 and all its entry points, resolved once (thread-safe: a function-local static). A
// missing library or entry point is an exception at the first parallel call, which the CLI reports
// as an internal error (exit 1) after removing unfinished outputs.
const Entries& entries() {
  static const Entries loaded = [] {
    Entries e;
    void* handle = ::dlopen(kTbbLibrary, RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      const char* why = ::dlerror();
      throw std::runtime_error(std::string("cannot load oneTBB: ") + (why ? why : kTbbLibrary));
    }
    for (std::size_t i = 0; i < kEntries; ++i) {
      e.fn[i] = ::dlsym(handle, kEntryNames[i]);
      if (!e.fn[i]) throw std::runtime_error(std::string("oneTBB (") + kTbbLibrary + ") lacks " + kEntryNames[i]);
    }
    g_loaded.store(true, std::memory_order_release);
    return e;
  }();
  return loaded;
}

template <typename Fn>
Fn entry(std::size_t i) {
  return reinterpret_cast<Fn>(entries().fn[i]);
}

// Whether some object in the process already is libtbb.so.12 (a plugin's libraries may load it).
bool tbb_in_process() {
  return ::dl_iterate_phdr(
             [](dl_phdr_info* info, std::size_t, void*) -> int {
               const std::string_view path = info->dlpi_name ? info->dlpi_name : "";
               const std::string_view name = path.substr(path.rfind('/') + 1);
               return name == kTbbLibrary ? 1 : 0;
             },
             nullptr) != 0;
}

// oneTBB 2021's default concurrency (governor::default_num_threads, AvailableHwConcurrency on Linux):
// the CPUs in the process's affinity mask, counted up to sysconf(_SC_NPROCESSORS_ONLN); that count
// if the mask cannot be read; at least 1. The kernel returns only active CPUs in the mask, so the
// cap never binds and is read only when the mask cannot be (reading it costs a file read of
// /sys/devices/system/cpu/online). (oneTBB also asks libiomp5, when that is loaded, to restore the
// mask it may have changed: no OpenMP runtime is in the process before oneTBB is.)
int default_concurrency() {
  static const int value = [] {
    for (std::size_t masks = 1;; masks <<= 1) {
      std::vector<cpu_set_t> mask(masks);
      const std::size_t bytes = sizeof(cpu_set_t) * masks;
      std::memset(mask.data(), 0, bytes);
      if (::sched_getaffinity(::getpid(), bytes, mask.data()) == 0) {
        long available = 0;
        for (std::size_t m = 0; m < masks; ++m) available += CPU_COUNT(&mask[m]);
        return available > 0 ? int(std::min<long>(available, INT_MAX)) : 1;
      }
      if (errno != EINVAL || bytes * CHAR_BIT >= 256 * 1024) break;
    }
    const long online = ::sysconf(_SC_NPROCESSORS_ONLN);
    return online > 0 ? int(std::min<long>(online, INT_MAX)) : 1;
  }();
  return value;
}

}  // namespace

#define HX_TBB_FORWARD(index, ret, name, params, args) \
  ret name params { return entry<ret(*) params>(index) args; }

namespace tbb::detail::r1 {

HX_TBB_FORWARD(0, void, spawn, (d1::task& t, d1::task_group_context& ctx), (t, ctx))
HX_TBB_FORWARD(1, void, spawn, (d1::task& t, d1::task_group_context& ctx, d1::slot_id id), (t, ctx, id))
HX_TBB_FORWARD(2, void, execute_and_wait,
               (d1::task& t, d1::task_group_context& t_ctx, d1::wait_context& w, d1::task_group_context& w_ctx),
               (t, t_ctx, w, w_ctx))
HX_TBB_FORWARD(3, void, wait, (d1::wait_context& w, d1::task_group_context& ctx), (w, ctx))
HX_TBB_FORWARD(4, d1::slot_id, execution_slot, (const d1::execution_data* ed), (ed))
HX_TBB_FORWARD(5, d1::task_group_context*, current_context, (), ())
HX_TBB_FORWARD(6, void, notify_waiters, (std::uintptr_t wait_ctx_addr), (wait_ctx_addr))
HX_TBB_FORWARD(7, void*, allocate, (d1::small_object_pool*& pool, std::size_t bytes, const d1::execution_data& ed),
               (pool, bytes, ed))
HX_TBB_FORWARD(8, void*, allocate, (d1::small_object_pool*& pool, std::size_t bytes), (pool, bytes))
HX_TBB_FORWARD(9, void, deallocate,
               (d1::small_object_pool& pool, void* ptr, std::size_t bytes, const d1::execution_data& ed),
               (pool, ptr, bytes, ed))
HX_TBB_FORWARD(10, void, deallocate, (d1::small_object_pool& pool, void* ptr, std::size_t bytes), (pool, ptr, bytes))
HX_TBB_FORWARD(11, void*, cache_aligned_allocate, (std::size_t size), (size))
HX_TBB_FORWARD(12, void, cache_aligned_deallocate, (void* p), (p))
HX_TBB_FORWARD(13, std::size_t, cache_line_size, (), ())
HX_TBB_FORWARD(14, void*, allocate_memory, (std::size_t size), (size))
HX_TBB_FORWARD(15, void, deallocate_memory, (void* p), (p))
HX_TBB_FORWARD(16, void, throw_exception, (exception_id id), (id))
HX_TBB_FORWARD(17, void, initialize, (d1::task_arena_base& ta), (ta))
HX_TBB_FORWARD(18, void, terminate, (d1::task_arena_base& ta), (ta))
HX_TBB_FORWARD(19, bool, attach, (d1::task_arena_base& ta), (ta))
HX_TBB_FORWARD(20, void, execute, (d1::task_arena_base& ta, d1::delegate_base& d), (ta, d))
HX_TBB_FORWARD(21, void, wait, (d1::task_arena_base& ta), (ta))
HX_TBB_FORWARD(23, void, isolate_within_arena, (d1::delegate_base& d, std::intptr_t isolation), (d, isolation))
HX_TBB_FORWARD(24, void, enqueue, (d1::task& t, d1::task_arena_base* ta), (t, ta))
HX_TBB_FORWARD(25, void, enqueue, (d1::task& t, d1::task_group_context& ctx, d1::task_arena_base* ta), (t, ctx, ta))
HX_TBB_FORWARD(26, void, initialize, (d1::task_group_context& ctx), (ctx))
HX_TBB_FORWARD(27, void, destroy, (d1::task_group_context& ctx), (ctx))
HX_TBB_FORWARD(28, void, reset, (d1::task_group_context& ctx), (ctx))
HX_TBB_FORWARD(29, bool, cancel_group_execution, (d1::task_group_context& ctx), (ctx))
HX_TBB_FORWARD(30, bool, is_group_execution_cancelled, (d1::task_group_context& ctx), (ctx))
HX_TBB_FORWARD(31, void, capture_fp_settings, (d1::task_group_context& ctx), (ctx))

// this_task_arena::max_concurrency() (ta == nullptr) before oneTBB is in the process: no thread is
// in an arena yet, so oneTBB would answer its default concurrency.
int max_concurrency(const d1::task_arena_base* ta) {
  if (ta == nullptr && !g_loaded.load(std::memory_order_acquire) && !tbb_in_process()) return default_concurrency();
  return entry<int (*)(const d1::task_arena_base*)>(22)(ta);
}

}  // namespace tbb::detail::r1

#undef HX_TBB_FORWARD
