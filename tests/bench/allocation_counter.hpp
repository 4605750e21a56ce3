// Counting heap allocations in a benchmark binary (docs/performance.md).
//
// Include in exactly one translation unit of a benchmark binary: it replaces the global
// operator new/delete and, on glibc, interposes malloc and friends.
#pragma once

#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <vector>

// --- Heap allocation counting -----------------------------------------------------------------
//
// Two counters, because Eigen does not allocate through operator new: its heap buffers come
// from std::malloc (Eigen/src/Core/util/Memory.h). Counting operator new alone would miss an
// accidentally dynamic Eigen temporary, the likeliest way for the kinematics to start
// allocating. So operator new is replaced (portable C++), and on glibc malloc and friends are
// interposed as well, forwarding to glibc's own __libc_* entry points.

namespace {
std::atomic<std::uint64_t> g_new_calls{0};
std::atomic<std::uint64_t> g_malloc_calls{0};

void* counted_new(std::size_t n) {
  g_new_calls.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(n == 0 ? 1 : n))
    return p;
  throw std::bad_alloc();
}

void* counted_new_aligned(std::size_t n, std::align_val_t al) {
  g_new_calls.fetch_add(1, std::memory_order_relaxed);
  const auto a = static_cast<std::size_t>(al);
  // aligned_alloc wants a size that is a multiple of the alignment.
  if (void* p = std::aligned_alloc(a, ((n == 0 ? 1 : n) + a - 1) / a * a))
    return p;
  throw std::bad_alloc();
}
}  // namespace

void* operator new(std::size_t n) {
  return counted_new(n);
}
void* operator new[](std::size_t n) {
  return counted_new(n);
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return counted_new(n);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, const std::nothrow_t& t) noexcept {
  return operator new(n, t);
}
void* operator new(std::size_t n, std::align_val_t al) {
  return counted_new_aligned(n, al);
}
void* operator new[](std::size_t n, std::align_val_t al) {
  return counted_new_aligned(n, al);
}
void operator delete(void* p) noexcept {
  std::free(p);
}
void operator delete[](void* p) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t) noexcept {
  std::free(p);
}
void operator delete(void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete[](void* p, const std::nothrow_t&) noexcept {
  std::free(p);
}
void operator delete(void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete(void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept {
  std::free(p);
}

#if defined(__GLIBC__)
extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* __libc_memalign(std::size_t, std::size_t);

// Every block still comes from glibc, so glibc's free() releases all of them unchanged.
void* malloc(std::size_t n) {
  g_malloc_calls.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(n);
}
void* calloc(std::size_t count, std::size_t n) {
  g_malloc_calls.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(count, n);
}
void* realloc(void* p, std::size_t n) {
  g_malloc_calls.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(p, n);
}
void* memalign(std::size_t alignment, std::size_t n) {
  g_malloc_calls.fetch_add(1, std::memory_order_relaxed);
  return __libc_memalign(alignment, n);
}
void* aligned_alloc(std::size_t alignment, std::size_t n) {
  g_malloc_calls.fetch_add(1, std::memory_order_relaxed);
  return __libc_memalign(alignment, n);
}
int posix_memalign(void** out, std::size_t alignment, std::size_t n) {
  g_malloc_calls.fetch_add(1, std::memory_order_relaxed);
  if (alignment % sizeof(void*) != 0 || (alignment & (alignment - 1)) != 0)
    return EINVAL;
  void* p = __libc_memalign(alignment, n);
  if (p == nullptr)
    return ENOMEM;
  *out = p;
  return 0;
}
}  // extern "C"
#endif

namespace redpost::bench {

// Records heap allocations made inside the timed loop, averaged per iteration.
class AllocationScope {
 public:
  // items_per_iteration > 1 (e.g. the poses of a path) reports the counts per item instead,
  // as "new/item" and "malloc/item".
  explicit AllocationScope(benchmark::State& state, double items_per_iteration = 1.0)
      : state_(state),
        items_(items_per_iteration),
        new0_(::g_new_calls.load(std::memory_order_relaxed)),
        malloc0_(::g_malloc_calls.load(std::memory_order_relaxed)) {}
  ~AllocationScope() {
    const auto news = ::g_new_calls.load(std::memory_order_relaxed) - new0_;
    const auto mallocs = ::g_malloc_calls.load(std::memory_order_relaxed) - malloc0_;
    const bool per_item = items_ != 1.0;
    const double scale = 1.0 / items_;
    state_.counters[per_item ? "new/item" : "new/iter"] =
        benchmark::Counter(static_cast<double>(news) * scale, benchmark::Counter::kAvgIterations);
#if defined(__GLIBC__)
    // Includes the mallocs behind operator new.
    state_.counters[per_item ? "malloc/item" : "malloc/iter"] = benchmark::Counter(
        static_cast<double>(mallocs) * scale, benchmark::Counter::kAvgIterations);
#else
    (void)mallocs;
#endif
  }

 private:
  benchmark::State& state_;
  double items_;
  std::uint64_t new0_, malloc0_;
};

// The counters must see an allocation, or the zeros they report would prove nothing: one
// through operator new, one through an Eigen dynamic matrix (malloc, not operator new).
inline bool allocation_counters_work() {
  const std::uint64_t news = ::g_new_calls.load(), mallocs = ::g_malloc_calls.load();
  auto* v = new std::vector<double>(100);
  benchmark::DoNotOptimize(v);
  delete v;
  const bool new_seen = ::g_new_calls.load() >= news + 2;  // the vector object and its buffer
#if defined(__GLIBC__)
  const std::uint64_t mallocs_before_eigen = ::g_malloc_calls.load();
  {
    Eigen::MatrixXd M(6, 9);
    benchmark::DoNotOptimize(M.data());
  }
  const bool malloc_seen =
      ::g_malloc_calls.load() >= mallocs + 2 && ::g_malloc_calls.load() > mallocs_before_eigen;
#else
  const bool malloc_seen = true;
#endif
  return new_seen && malloc_seen;
}

// The main() of a benchmark binary: refuses to run with counters that would report zeros
// for the wrong reason.
inline int run_benchmarks(int argc, char** argv) {
  if (!allocation_counters_work()) {
    std::fprintf(stderr, "heap allocation counters do not work in this build\n");
    return 1;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv))
    return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace redpost::bench
