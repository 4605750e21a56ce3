// The bodies of one cell, tool and set-up together: which pairs must stay apart, where each
// body is at a posture, the distance between two bodies (FCL), and how far any point of a body
// can move for given joint steps (docs/collision.md).
//
// The scene is read-only once made: one scene may serve several threads, each with its own
// ScenePoses. A tool change makes a new scene (its bodies differ); the set-up's and the cell's
// geometry is shared between scenes, not copied.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "redpost/collision/body.hpp"
#include "redpost/kinematics/cell.hpp"
#include "redpost/kinematics/forward_kinematics.hpp"

namespace redpost {

// Where every body of a scene is, in {B}: made by CollisionScene::place(), sized once and reused
// (no allocation per pose).
struct ScenePoses {
  std::vector<Isometry> T_B_body;
  std::vector<Eigen::Vector3d> centre_B;  // each body's bounding sphere's centre
};

// Two bodies that must keep the margin between them.
struct BodyPair {
  int a = 0, b = 0;  // body indices, a < b
};

// The nearest points of a pair (in {B}), where the distance was computed exactly.
struct Proximity {
  double distance_mm = 0.0;
  Eigen::Vector3d point_a_B = Eigen::Vector3d::Zero();
  Eigen::Vector3d point_b_B = Eigen::Vector3d::Zero();
  bool exact = false;  // false: a lower bound from bounding spheres, no points
};

struct BodyGeometry;  // FCL's objects of one body (scene.cpp)

class CollisionScene {
 public:
  // `cell` is the chain the bodies' frames belong to (its TCP: the tool's). `allowed`: pairs of
  // body indices never checked. Pairs are also left out where the two bodies cannot move
  // against each other (one frame, both static), among the tool's bodies and between the tool
  // and the cell's bodies that carry it (no physical joint between them), and between the
  // cutter and the part. Geometry given by `shared` (an earlier scene of the same bodies in the
  // same order, for its first `shared_count` bodies) is reused. The scene keeps a pointer to
  // the cell: it must outlive the scene.
  CollisionScene(const Cell& cell, std::vector<Body> bodies,
                 const std::vector<std::pair<int, int>>& allowed,
                 const CollisionScene* shared = nullptr, int shared_count = 0);
  ~CollisionScene();
  CollisionScene(const CollisionScene&) = delete;
  CollisionScene& operator=(const CollisionScene&) = delete;

  const Cell& cell() const { return *cell_; }
  int body_count() const { return static_cast<int>(bodies_.size()); }
  const Body& body(int i) const { return bodies_[static_cast<std::size_t>(i)]; }
  const std::vector<BodyPair>& pairs() const { return pairs_; }
  // The joints that move body i (chain order; the tool's spin left out of the tool's bodies).
  const std::vector<int>& movers(int i) const { return movers_[static_cast<std::size_t>(i)]; }
  // "spindle vs fixture vise.stl"
  std::string pair_name(int pair) const;

  // Sizes `poses` for this scene (once; place() then allocates nothing).
  void prepare(ScenePoses& poses) const;
  // The bodies' poses at the posture `data` was computed for (forward_kinematics with link
  // frames).
  void place(const KinematicsData& data, ScenePoses& poses) const;
  // One body put at T_B_body by hand (tests, a body drawn where the chain does not put it).
  void set_pose(int body, const Isometry& T_B_body, ScenePoses& poses) const;

  // A lower bound of the distance between the pair's bodies at `poses` (mm; 0 or less where they
  // touch or overlap), exact (FCL) wherever it is below `exact_below_mm`: above it, the bodies'
  // shapes' bounding spheres give the bound.
  double distance(int pair, const ScenePoses& poses, double exact_below_mm,
                  Proximity* where = nullptr) const;

  // True where one body of the pair lies wholly inside the other's closed mesh (a fixture or
  // the part): surface distances cannot see that. Needed where no motion leads in from a known
  // clear posture (the first pose of a program).
  bool inside(int pair, const ScenePoses& poses) const;

  // For a motion from the posture of `data` and `poses` by joint steps |dq| (DH units; each
  // joint's largest departure from its start along the motion), bounds on how far any point of
  // each body can move (mm). Conservative advancement (docs/collision.md, "The bound"): a
  // revolute joint k moves a point at most |dq_k| times its distance from the axis, which the
  // joints after k can grow by their own motion. `from` gets body_count() rows of
  // cell().size() + 1 entries: row b, entry k is the bound of body b's motion by the joints k
  // and after (entry 0 its whole motion in {B}, the last 0).
  void motion_bounds(const KinematicsData& data, const ScenePoses& poses, const JointVector& dq,
                     std::vector<double>& from) const;
  // How far the pair's distance can change, from motion_bounds' rows: the joints up to the frame
  // of the body nearer the chain's start move both bodies alike, so only the later body's motion
  // by the joints after that frame counts (the chain is serial); and where the nearer body is
  // round about the next joint's axis (a rotary table's top), that joint's turn changes no
  // distance either, so the motion counts from the joint after it (first_mover).
  double pair_motion(int pair, const std::vector<double>& from) const {
    const auto p = static_cast<std::size_t>(pair);
    return from[static_cast<std::size_t>(pair_mover_[p]) * row_ +
                static_cast<std::size_t>(pair_from_[p])];
  }
  // The first joint (chain index) whose motion counts in pair_motion; cell().size(): none.
  int first_mover(int pair) const { return pair_from_[static_cast<std::size_t>(pair)]; }

 private:
  const Cell* cell_;
  std::vector<Body> bodies_;
  std::vector<std::shared_ptr<const BodyGeometry>> geometry_;
  std::vector<BodyPair> pairs_;
  // Per body: its bounding sphere in its frame, and the joints that move it (chain order).
  std::vector<Eigen::Vector3d> centre_;
  std::vector<double> radius_;
  std::vector<std::vector<int>> movers_;
  // Per pair: the body whose motion counts and the first joint that moves it against the other.
  std::vector<int> pair_mover_, pair_from_;
  std::size_t row_ = 1;  // cell().size() + 1
};

}  // namespace redpost
