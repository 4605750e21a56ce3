// Forward kinematics and Jacobian of the 9-joint Andres cell: redpost against Orocos KDL on the
// same chain, plus a count of heap allocations per call (docs/performance.md).
//
// Run: build/tests/bench/redpost_bench_kinematics --benchmark_repetitions=5
//        --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <random>
#include <vector>

#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/jacobian.hpp>
#include <kdl/jntarray.hpp>

#include "kdl_chain.hpp"
#include "redpost/forward_kinematics.hpp"
#include "redpost/jacobian.hpp"
#include "test_support.hpp"

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

namespace {

constexpr std::size_t kPostureCount = 1024;  // a power of two: the index wraps with a mask
constexpr std::uint64_t kSeed = 20110101;

struct Workload {
  redpost::Cell cell;
  std::vector<redpost::JointVector> q;
  std::vector<KDL::JntArray> q_kdl;
  KDL::Chain chain;
};

// Built once, outside every timed loop.
const Workload& workload() {
  static const Workload w = [] {
    Workload out;
    out.cell = redpost::test::shipped_cell("andres2011_kr15_track_table");
    std::mt19937_64 rng(kSeed);
    for (std::size_t k = 0; k < kPostureCount; ++k) {
      out.q.push_back(redpost::test::random_posture(out.cell, rng));
      KDL::JntArray qk(static_cast<unsigned>(out.cell.size()));
      for (int i = 0; i < out.cell.size(); ++i) {
        qk(static_cast<unsigned>(i)) = out.q.back()[i];
      }
      out.q_kdl.push_back(qk);
    }
    out.chain = redpost::test::kdl_chain_from_cell(out.cell);
    return out;
  }();
  return w;
}

// Records heap allocations made inside the timed loop, averaged per iteration.
class AllocationScope {
 public:
  explicit AllocationScope(benchmark::State& state)
      : state_(state),
        new0_(g_new_calls.load(std::memory_order_relaxed)),
        malloc0_(g_malloc_calls.load(std::memory_order_relaxed)) {}
  ~AllocationScope() {
    const auto news = g_new_calls.load(std::memory_order_relaxed) - new0_;
    const auto mallocs = g_malloc_calls.load(std::memory_order_relaxed) - malloc0_;
    state_.counters["new/iter"] =
        benchmark::Counter(static_cast<double>(news), benchmark::Counter::kAvgIterations);
#if defined(__GLIBC__)
    // Includes the mallocs behind operator new.
    state_.counters["malloc/iter"] =
        benchmark::Counter(static_cast<double>(mallocs), benchmark::Counter::kAvgIterations);
#else
    (void)mallocs;
#endif
  }

 private:
  benchmark::State& state_;
  std::uint64_t new0_, malloc0_;
};

void BM_redpost_fk(benchmark::State& state) {
  const Workload& w = workload();
  redpost::KinematicsData data;
  std::size_t k = 0;
  {
    AllocationScope allocations(state);
    for (auto _ : state) {
      redpost::forward_kinematics(w.cell, w.q[k++ & (kPostureCount - 1)], data);
      benchmark::DoNotOptimize(data.T_B_tcp);
    }
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_redpost_fk);

void BM_redpost_fk_jacobian(benchmark::State& state) {
  const Workload& w = workload();
  redpost::KinematicsData data;
  redpost::Jacobian J;
  std::size_t k = 0;
  {
    AllocationScope allocations(state);
    for (auto _ : state) {
      redpost::forward_kinematics(w.cell, w.q[k++ & (kPostureCount - 1)], data);
      redpost::tcp_jacobian(w.cell, data, J);
      benchmark::DoNotOptimize(data.T_B_tcp);
      benchmark::DoNotOptimize(J);
    }
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_redpost_fk_jacobian);

// KDL's FK alone, for a like-for-like comparison with BM_redpost_fk.
void BM_kdl_fk(benchmark::State& state) {
  const Workload& w = workload();
  KDL::ChainFkSolverPos_recursive fk(w.chain);
  KDL::Frame F;
  std::size_t k = 0;
  {
    AllocationScope allocations(state);
    for (auto _ : state) {
      fk.JntToCart(w.q_kdl[k++ & (kPostureCount - 1)], F);
      benchmark::DoNotOptimize(F);
    }
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_kdl_fk);

void BM_kdl_fk_jacobian(benchmark::State& state) {
  const Workload& w = workload();
  KDL::ChainFkSolverPos_recursive fk(w.chain);
  KDL::ChainJntToJacSolver jac_solver(w.chain);
  KDL::Frame F;
  KDL::Jacobian J(w.chain.getNrOfJoints());
  std::size_t k = 0;
  {
    AllocationScope allocations(state);
    for (auto _ : state) {
      const KDL::JntArray& q = w.q_kdl[k++ & (kPostureCount - 1)];
      fk.JntToCart(q, F);
      jac_solver.JntToJac(q, J);
      benchmark::DoNotOptimize(F);
      benchmark::DoNotOptimize(J.data);
    }
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_kdl_fk_jacobian);

// The counters must see an allocation, or the zeros they report would prove nothing: one
// through operator new, one through an Eigen dynamic matrix (malloc, not operator new).
bool allocation_counters_work() {
  const std::uint64_t news = g_new_calls.load(), mallocs = g_malloc_calls.load();
  auto* v = new std::vector<double>(100);
  benchmark::DoNotOptimize(v);
  delete v;
  const bool new_seen = g_new_calls.load() >= news + 2;  // the vector object and its buffer
#if defined(__GLIBC__)
  const std::uint64_t mallocs_before_eigen = g_malloc_calls.load();
  {
    Eigen::MatrixXd M(6, 9);
    benchmark::DoNotOptimize(M.data());
  }
  const bool malloc_seen =
      g_malloc_calls.load() >= mallocs + 2 && g_malloc_calls.load() > mallocs_before_eigen;
#else
  const bool malloc_seen = true;
#endif
  return new_seen && malloc_seen;
}

}  // namespace

int main(int argc, char** argv) {
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
