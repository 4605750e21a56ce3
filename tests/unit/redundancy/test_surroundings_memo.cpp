// The planner's memo of the links around the arm (redundancy/surroundings_memo.hpp): what it
// gives is what ArmIk::before_arm and after_arm compose, bit for bit, whatever it remembers; and
// a solver built where an earlier one stood does not get the earlier one's frames.
#include <optional>
#include <random>

#include "catch_compat.hpp"
#include "redundancy/surroundings_memo.hpp"
#include "test_support.hpp"

using namespace redpost;

namespace {

bool same(const Isometry& a, const Isometry& b) {
  return a.matrix() == b.matrix();
}

// The memo's answer against the solver's own composition, bit for bit.
bool as_composed(detail::SurroundingsMemo& memo, const ArmIk& ik, const JointVector& q) {
  ArmBefore before;
  ArmAfter after;
  ik.before_arm(q, before);
  ik.after_arm(q, after);
  const ArmBefore& b = memo.before(ik, q);
  const ArmAfter& a = memo.after(ik, q);
  return same(b.T_B_pre, before.T_B_pre) && same(b.T_C_B, before.T_C_B) &&
         same(a.T_6_tcp, after.T_6_tcp) && same(a.T_tcp_C6, after.T_tcp_C6);
}

}  // namespace

TEST_CASE("surroundings memo: the same frames as composed, for settings met again and not") {
  // Settings drawn from a few values per joint, as a keyframe's lattice has them, so that most
  // are met again (and many slots collide); two solvers of different cells in turn.
  const Cell andres = test::shipped_cell("andres2011_kr15_track_table");
  const Cell caro = test::shipped_cell("caro2014_kr270_table");
  const ArmIk ik_andres(andres), ik_caro(caro);
  detail::SurroundingsMemo memo;
  std::mt19937_64 rng(20261205);
  std::uniform_int_distribution<int> pick(0, 11);
  int wrong = 0;
  for (int n = 0; n < 20000; ++n) {
    const bool first = n % 3 != 0;
    const Cell& cell = first ? andres : caro;
    const ArmIk& ik = first ? ik_andres : ik_caro;
    JointVector q = cell.home();
    for (int i = 0; i < cell.size(); ++i) {
      const Joint& j = cell.joint(i);
      q[i] = j.lower + (j.upper - j.lower) * pick(rng) / 11.0;
    }
    wrong += as_composed(memo, ik, q) ? 0 : 1;
  }
  CHECK(wrong == 0);
}

TEST_CASE("surroundings memo: a solver built at a freed solver's address gets its own frames") {
  // The session builds a new ArmIk after a tool change, often where the last one stood. The
  // memo keys on the solver's instance, not on its address.
  const Cell cell = test::shipped_cell("andres2011_kr15_track_table");
  Cell moved = cell;
  moved.T_B_0.translation() += Eigen::Vector3d(250.0, -40.0, 10.0);
  std::optional<ArmIk> ik;
  ik.emplace(cell);
  const ArmIk* address = &*ik;
  detail::SurroundingsMemo memo;
  const JointVector q = cell.home();
  REQUIRE(as_composed(memo, *ik, q));
  ik.reset();
  ik.emplace(moved);
  REQUIRE(&*ik == address);
  CHECK(as_composed(memo, *ik, q));
  CHECK_FALSE(same(memo.before(*ik, q).T_B_pre, [&] {
    ArmBefore s;
    ArmIk(cell).before_arm(q, s);
    return s.T_B_pre;
  }()));
}
