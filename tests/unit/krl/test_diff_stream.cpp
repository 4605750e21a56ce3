// redpost diff as a stream: the sliding path window against brute force, the windowed alignment
// against edits whose count is known, and the file reader threads (errors, early stops).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "catch_compat.hpp"
#include "krl/diff_path.hpp"
#include "redpost/io/error.hpp"
#include "redpost/krl/diff.hpp"

using namespace redpost;
namespace fs = std::filesystem;

namespace {

KrlMotionRecord lin(int line, double x, double y, double z, int cl) {
  KrlMotionRecord m;
  m.keyword = "LIN";
  m.target.type = "E6POS";
  m.target.values = {{"X", x}, {"Y", y}, {"Z", z}, {"A", 0}, {"B", 90}, {"C", 0}, {"E1", 10}};
  m.file = "P.src";
  m.line = line;
  m.cl_line = cl;
  return m;
}

// Distance from q to the segment ab (or the point a when b is null).
double segment_distance(const std::array<double, 3>& q, const std::array<double, 3>& a,
                        const std::array<double, 3>* b) {
  double ab[3] = {0, 0, 0}, aq[3], len2 = 0, dot = 0;
  for (int k = 0; k < 3; ++k) {
    aq[k] = q[k] - a[k];
    if (b)
      ab[k] = (*b)[k] - a[k];
    len2 += ab[k] * ab[k];
    dot += aq[k] * ab[k];
  }
  const double t = len2 > 0 ? std::clamp(dot / len2, 0.0, 1.0) : 0.0;
  double d2 = 0;
  for (int k = 0; k < 3; ++k)
    d2 += (aq[k] - t * ab[k]) * (aq[k] - t * ab[k]);
  return std::sqrt(d2);
}

// A program of n motions with unique positions, CL lines 100, 110, ... when `cl`.
struct Program {
  KrlProgram p;
  int next_line = 10;
  void add(double x, double y, double z, int cl) {
    p.motions.push_back(lin(next_line++, x, y, z, cl));
  }
};

void write_program(const fs::path& file, int motions, int bad_line = 0) {
  std::ofstream out(file, std::ios::binary);
  out << "DEF " << file.stem().string() << "( )\n$VEL.CP = 0.1\n";
  int line = 3;
  for (int i = 0; i < motions; ++i, ++line) {
    if (line == bad_line)
      out << "LIN {X 1, Y}\n";
    else
      out << "LIN {X " << i * 0.5 << ", Y " << (i % 40) * 2.0 << ", Z 5, A 0, B 90, C 0}\n";
  }
  out << "END\n";
}

}  // namespace

TEST_CASE("diff path window: nearest segment as brute force over the points it holds") {
  std::mt19937 rng(20261205);
  std::uniform_real_distribution<double> step(-3.0, 3.0), off(-4.0, 4.0);
  std::uniform_int_distribution<int> coin(0, 19);
  krl::PathWindow window(2.0);
  std::vector<krl::PathPoint> all;
  std::array<double, 3> at{0, 0, 0};
  size_t largest = 0;
  const size_t back = 150;
  for (std::uint64_t seq = 0; seq < 3000; ++seq) {
    for (double& c : at)
      c += step(rng);
    const krl::PathPoint p{at, {0, 90, 0}, coin(rng) == 0, seq};
    window.push(p);
    all.push_back(p);
    if (seq > back)
      window.drop_before(seq - back);
    largest = std::max(largest, window.size());
    // The window holds the points of motions seq - back .. seq (and no more).
    const size_t first = seq > back ? static_cast<size_t>(seq - back) : 0;
    REQUIRE(window.size() == all.size() - first);
    for (int q = 0; q < 3; ++q) {
      const std::array<double, 3> x{at[0] + off(rng), at[1] + off(rng), at[2] + off(rng)};
      double brute = std::numeric_limits<double>::infinity();
      for (size_t i = first; i < all.size(); ++i) {
        const bool segment = i + 1 < all.size() && !all[i + 1].starts_piece;
        brute =
            std::min(brute, segment_distance(x, all[i].xyz, segment ? &all[i + 1].xyz : nullptr));
      }
      const krl::PathWindow::Nearest n = window.nearest({x, {0, 90, 0}, false, 0});
      if (n.exact)
        CHECK(n.distance_mm == Approx(brute).margin(1e-12));
      else
        CHECK(n.distance_mm <= brute + 1e-12);  // a lower bound
    }
  }
  CHECK(largest == back + 1);
}

// Issue 48: the shapes that made the search's work grow with the window (every motion at one
// point, a path back and forth over itself, a cloud around one point), against brute force
// over the points the window holds. Exact where the search neither capped nor gave up; an upper
// bound where it capped; and the number of segments a query examines stays bounded.
TEST_CASE("diff path window: degenerate shapes against brute force, with bounded work") {
  std::mt19937 rng(48);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (const int shape : {0, 1, 2, 3}) {
    INFO("shape " << shape << " (0 one point, 1 back and forth, 2 a cloud, 3 both orientations)");
    krl::PathWindow window(1.0);
    std::vector<krl::PathPoint> all;
    const size_t back = 3000;
    size_t capped = 0, queries = 0;
    for (std::uint64_t seq = 0; seq < 8000; ++seq) {
      std::array<double, 3> at{0, 0, 0};
      std::array<double, 3> abc{0, 90, 0};
      const double phase = static_cast<double>(seq % 200);
      if (shape == 1 || shape == 3)
        at[0] = phase < 100 ? phase * 0.5 : (200 - phase) * 0.5;
      if (shape == 2)
        at = {0.01 * u(rng), 0.01 * u(rng), 0.01 * u(rng)};
      if (shape == 3)
        abc[2] = seq % 2 == 0 ? 0.0 : 10.0;  // the same places, two orientations: no merging
      const krl::PathPoint p{at, abc, false, seq};
      window.push(p);
      all.push_back(p);
      if (seq > back)
        window.drop_before(seq - back);
      REQUIRE(window.size() == all.size() - (seq > back ? seq - back : 0));
      if (seq % 37 != 0)
        continue;
      const size_t first = seq > back ? static_cast<size_t>(seq - back) : 0;
      for (int q = 0; q < 2; ++q) {
        const std::array<double, 3> x{at[0] + 0.3 * u(rng), at[1] + 0.3 * u(rng),
                                      at[2] + 0.3 * u(rng)};
        double brute = std::numeric_limits<double>::infinity();
        for (size_t i = first; i < all.size(); ++i) {
          const bool segment = i + 1 < all.size() && !all[i + 1].starts_piece;
          brute =
              std::min(brute, segment_distance(x, all[i].xyz, segment ? &all[i + 1].xyz : nullptr));
        }
        const krl::PathWindow::Nearest n = window.nearest({x, abc, false, seq});
        ++queries;
        capped += n.capped ? 1 : 0;
        if (n.capped)
          CHECK(n.distance_mm >= brute - 1e-12);  // the least of those examined
        else if (n.exact)
          CHECK(n.distance_mm == Approx(brute).margin(1e-12));
        // A query on the path (a point the window holds) ends at once.
        const krl::PathWindow::Nearest on = window.nearest({at, abc, false, seq});
        CHECK(on.distance_mm <= krl::PathWindow::kOnPathMm);
        CHECK_FALSE(on.capped);
      }
    }
    INFO(capped << " of " << queries << " queries capped");
    // Only the cloud (no two points alike) crowds the search past its bound.
    if (shape == 2)
      CHECK(capped > 0);
    else
      CHECK(capped == 0);
  }
}

// The search stops at a segment within enough_mm: the distance reported is then at most that.
TEST_CASE("diff path window: a segment near enough ends the search") {
  krl::PathWindow window(1.0);
  for (std::uint64_t seq = 0; seq < 100; ++seq)
    window.push({{seq * 0.5, 0.0, 0.0}, {0, 90, 0}, false, seq});
  const std::array<double, 3> x{10.2, 0.00005, 0.0};
  const krl::PathWindow::Nearest exact = window.nearest({x, {0, 90, 0}, false, 20});
  CHECK(exact.distance_mm == Approx(0.00005).margin(1e-12));
  const krl::PathWindow::Nearest enough = window.nearest({x, {0, 90, 0}, false, 20}, 0.0001);
  CHECK(enough.distance_mm <= 0.0001);
  CHECK(enough.distance_mm >= exact.distance_mm);
}

TEST_CASE("diff stream: edits found exactly with a window far smaller than the programs") {
  // Seeded random edits, spaced wider than the window: removed runs, inserted runs, moved
  // points. Every window size, with and without CL lines, must count exactly what was done.
  std::mt19937 rng(31);
  for (int trial = 0; trial < 6; ++trial) {
    const bool cl = trial % 2 == 1;
    Program a, b;
    size_t removed = 0, inserted = 0, changed = 0;
    const int n = 4000;
    std::uniform_int_distribution<int> kind(0, 3), size(1, 12);
    int next_edit = 150;
    for (int i = 0; i < n; ++i) {
      const double x = i * 0.7, y = (i % 50) * 3.0;
      const int cl_line = cl ? 100 + 10 * i : 0;
      a.add(x, y, 5.0, cl_line);
      if (i != next_edit) {
        b.add(x, y, 5.0, cl_line);
        continue;
      }
      next_edit += 150 + size(rng) * 10;
      switch (kind(rng)) {
        case 0:  // removed (this one)
          ++removed;
          break;
        case 1: {  // a run inserted after it, at new places (and new CL lines)
          b.add(x, y, 5.0, cl_line);
          const int k = size(rng);
          for (int j = 0; j < k; ++j)
            b.add(x + 0.3, y + 100.0 + j, 40.0, cl ? cl_line + 1 + j : 0);
          inserted += static_cast<size_t>(k);
          break;
        }
        case 2:  // moved by 0.35 mm (a new key)
          b.add(x, y, 5.35, cl_line);
          ++changed;
          break;
        default:  // moved by 0.02 mm (the same key)
          b.add(x, y, 5.02, cl_line);
          ++changed;
          break;
      }
    }
    for (size_t window : {size_t{64}, size_t{300}, size_t{1000000}}) {
      KrlDiffOptions o;
      o.window = window;
      const KrlDiffResult r = diff_krl_programs(a.p, b.p, o);
      INFO("trial " << trial << ", window " << window);
      CHECK(r.aligned_by_cl_line == cl);
      CHECK(r.removed == removed);
      CHECK(r.inserted == inserted);
      CHECK(r.changed == changed);
      CHECK(r.compared == a.p.motions.size() - removed);
      CHECK(r.unaligned_regions == 0);
      CHECK_FALSE(r.budget_exhausted);
      CHECK(r.window == window);
    }
  }
}

TEST_CASE("diff stream: a block longer than the window") {
  // 3000 motions inserted in one place. By CL lines the merge walk aligns it with any window;
  // by position it needs a window of more than twice its length, and says so when it has not.
  for (bool cl : {true, false}) {
    Program a, b;
    for (int i = 0; i < 6000; ++i) {
      a.add(i * 0.7, (i % 50) * 3.0, 5.0, cl ? 100 + 10 * i : 0);
      b.add(i * 0.7, (i % 50) * 3.0, 5.0, cl ? 100 + 10 * i : 0);
      if (i == 2000)
        for (int j = 0; j < 3000; ++j)
          b.add(j * 0.5, 500.0, 60.0, cl ? 100 + 10 * i + 1 : 0);
    }
    KrlDiffOptions o;
    o.window = 1000;
    const KrlDiffResult small = diff_krl_programs(a.p, b.p, o);
    o.window = 8000;
    const KrlDiffResult large = diff_krl_programs(a.p, b.p, o);
    INFO("by CL line: " << cl);
    CHECK(large.inserted == 3000);
    CHECK(large.removed == 0);
    CHECK(large.changed == 0);
    CHECK(large.unaligned_regions == 0);
    if (cl) {
      CHECK(small.inserted == 3000);
      CHECK(small.changed == 0);
      CHECK(small.unaligned_regions == 0);
    } else {
      CHECK(small.unaligned_regions > 0);
      CHECK(small.unaligned_line_a > 0);
      CHECK(small.unaligned_line_b > 0);
      const std::string text = format_krl_diff_text(small, o);
      CHECK(text.find("within the window of 1000 motions") != std::string::npos);
      CHECK(text.find("A larger --window may align") != std::string::npos);
      CHECK(format_krl_diff_json(small, o).find("\"unaligned\": {\"regions\": ") !=
            std::string::npos);
    }
  }
}

TEST_CASE("diff stream: CL lines that go back fall back to alignment by key") {
  // Two runs of the same CL lines (a program that repeats a CL file's moves): the merge walk
  // cannot pair runs of equal CL line in order, the key (CL line and position) still can.
  Program a;
  for (int rep = 0; rep < 2; ++rep)
    for (int i = 0; i < 500; ++i)
      a.add(i * 0.7, rep * 50.0, 5.0, 100 + i);
  Program b = a;
  b.p.motions.erase(b.p.motions.begin() + 700);
  KrlDiffOptions o;
  o.window = 200;
  const KrlDiffResult r = diff_krl_programs(a.p, b.p, o);
  CHECK(r.aligned_by_cl_line);
  CHECK(r.removed == 1);
  CHECK(r.inserted == 0);
  CHECK(r.changed == 0);
}

TEST_CASE("diff stream: files read on threads, errors in order, early stops") {
  const fs::path dir = fs::temp_directory_path() / "redpost_diff_stream_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  // More motions than the reader threads' queues hold (4096), so that a reader is blocked when
  // the other side fails.
  write_program(dir / "A.src", 20000);
  write_program(dir / "B.src", 20000);
  write_program(dir / "BAD.src", 20000, 15000);
  KrlDiffOptions o;
  const KrlDiffResult same = diff_krl_paths((dir / "A.src").string(), (dir / "B.src").string(), o);
  CHECK(same.equal);
  CHECK(same.compared == 20000);
  // The same as the programs read whole.
  const KrlDiffResult whole = diff_krl_programs(read_krl_program((dir / "A.src").string()),
                                                read_krl_program((dir / "B.src").string()), o);
  CHECK(whole.compared == same.compared);
  for (size_t q = 0; q < whole.statistics.size(); ++q) {
    CHECK(whole.statistics[q].compared == same.statistics[q].compared);
    CHECK(whole.statistics[q].max == same.statistics[q].max);
  }

  const auto error_of = [&](const fs::path& x, const fs::path& y) {
    try {
      diff_krl_paths(x.string(), y.string(), o);
    } catch (const Error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  // A missing file while the other side's reader is blocked on its full queue.
  CHECK(error_of(dir / "A.src", dir / "MISSING.src").find("MISSING.src") != std::string::npos);
  CHECK(error_of(dir / "MISSING.src", dir / "A.src").find("MISSING.src") != std::string::npos);
  // A bad line late in one program is reported at its line, whichever side it is on.
  CHECK(error_of(dir / "A.src", dir / "BAD.src").find("BAD.src:15000") != std::string::npos);
  CHECK(error_of(dir / "BAD.src", dir / "A.src").find("BAD.src:15000") != std::string::npos);
  fs::remove_all(dir);
}
