// The clearance along a program, proven between the poses (docs/collision.md, "The bound").
//
// A ClearanceMonitor follows the written motions one after the other. For each pair of bodies
// that must stay apart it keeps a lower bound of their distance at the current posture. A
// motion whose bound on how far any body point can move (CollisionScene::motion_bounds) leaves
// every pair above the margin is proven clear as a whole; where it does not, the motion is
// split in two at its middle (the joints there from the motion's own path), distances are
// computed there, and so on, until each piece is proven or a distance below the margin is found.
// A collision between two samples is then impossible: the bound covers every configuration on
// the piece, not only its ends. Far pairs cost a subtraction per motion; distances are computed
// only where a pair's bound runs low.
//
// For a joint-linear path (PTP) the bound is exact. For a Cartesian one (LIN, CIRC) the joints
// between two samples are bounded by the chord between them plus twice the path's measured
// distance from the chord at its middle (the arm's joints are smooth functions of the path:
// their distance from the chord peaks near the middle); docs/collision.md states this limit.
#pragma once

#include <limits>
#include <vector>

#include "redpost/collision/joint_path.hpp"
#include "redpost/collision/scene.hpp"

namespace redpost {

struct ClearanceSettings {
  double margin_mm = 5.0;  // the least distance kept between bodies that may not touch
  // Distances below margin + exact_within_mm are computed exactly (FCL); above, the bodies'
  // bounding spheres bound them.
  double exact_within_mm = 100.0;
  // A pair's bound is computed anew once it falls below margin + refresh_within_mm.
  double refresh_within_mm = 25.0;
  int max_depth = 30;  // halvings of one motion before it is called unproven
  // Pieces one motion may be halved into in all, before it is called unproven: max_depth alone
  // allows 2^30 where a bound never closes (a body of absurd size, a distance that is not a
  // number), and the check must end in bounded work whatever it is given.
  int max_pieces = 4096;
  // How close to the margin a proof may end (mm): a pair that runs along at nearly the margin
  // would otherwise be halved without end. The check proves every distance >= margin -
  // resolution; the exact distances it computes must be >= margin.
  double resolution_mm = 0.01;
  // Scales the motion bound. 1 is the proven bound; below 1 the guarantee is gone. For the
  // mutation test only, which must see a bound that takes steps twice too long fail.
  double bound_scale = 1.0;
};

// What one motion (or a posture) came to.
struct MotionClearance {
  // Where clear: a lower bound of the least distance between any pair along the motion (mm).
  // Where not: a distance below the margin found on it (the check stops there, so the least may
  // be lower still), or the bound it could not prove. And the pair.
  double least_mm = std::numeric_limits<double>::infinity();
  int pair = -1;
  double s = 0.0;  // where along the motion (0 start, 1 end)
  // False: a pair comes closer than the margin (or cannot be proven not to), or the path is lost.
  bool clear = true;
  // Not clear for want of a proof: the bound did not close within max_depth halvings (or
  // max_pieces pieces), while no distance computed on it is below the margin (least_mm is then
  // that bound). A path whose joints move by more than its sampling can see, not a contact found.
  bool unproven = false;
  // The arm cannot follow the motion's path somewhere (its IK fails in the posture it starts
  // in): no distance there, so not proven clear.
  bool path_lost = false;
  // The nearest points where the least was computed exactly ({B}); exact false otherwise.
  Proximity where;
  // The least distance computed exactly on the motion (at its end and where it was halved),
  // over the pairs within reach of the margin: what a sampling sees, no bound (+inf: none
  // computed). With its pair and nearest points ({B}).
  double nearest_mm = std::numeric_limits<double>::infinity();
  int nearest_pair = -1;
  Proximity nearest_where;
  long distance_queries = 0;  // for the benchmark
};

// What a motion that is not clear came to, for its message: a distance computed at or below 0
// (touching), a bound that did not close where no computed distance is below the margin
// (unproven: no contact was found, so none is claimed), or a distance computed below the margin.
enum class ClearanceShortfall { touching, unproven, too_close };
ClearanceShortfall shortfall(const MotionClearance& c);

// The least distance over the scene's pairs at the posture q (mm), exact below `enough` and a
// lower bound above it; stops early once a pair is below `enough`. `poses` must be prepared for
// the scene (CollisionScene::prepare). For the planners' posture checks; `pair` gets the pair.
double posture_clearance(const CollisionScene& scene, const JointVector& q, double enough,
                         ScenePoses& poses, KinematicsData& data, int* pair = nullptr);

class ClearanceMonitor {
 public:
  // The scene must outlive the monitor.
  ClearanceMonitor(const CollisionScene& scene, const ClearanceSettings& settings);
  ~ClearanceMonitor();

  // Starts anew at the posture q (the first pose of a program, after a tool change): every pair
  // computed, and a body wholly inside a closed mesh found.
  MotionClearance start(const JointVector& q);
  // The motion along `path` from the current posture (path.at(0)) to its end, which becomes the
  // current posture.
  MotionClearance advance(const JointPath& path);
  // The motion along `path` from fresh distances at its start, leaving the monitor as it was:
  // for trying an alternative (a rapid routed another way).
  MotionClearance probe(const JointPath& path);

  bool started() const { return started_; }
  const JointVector& q() const;  // the current posture
  const ClearanceSettings& settings() const { return settings_; }
  const CollisionScene& scene() const { return *scene_; }
  long distance_queries() const { return queries_; }

 private:
  struct Node;
  Node& node(int i);
  const Node& node(int i) const;
  void compute(Node& n, bool fresh, MotionClearance& out, double s);
  void set_posture(Node& n, const JointVector& q);
  void interval(const JointPath& path, int depth, const Node& a, const Node& b,
                const std::vector<int>& pairs, MotionClearance& out);
  void bound(const Node& a, const Node& b, const Node* mid, double allowance,
             std::vector<double>& pair_bound);

  const CollisionScene* scene_;
  ClearanceSettings settings_;
  std::vector<Node> nodes_;  // 0: the current posture; 1: the motion's end; 2...: the halvings
  std::vector<double> body_bound_;
  std::vector<double> pair_bound_;
  std::vector<double> blend_;        // per pair: the blend's allowance of the motion being checked
  std::vector<double> last_motion_;  // per pair: the bound of the last motion's whole path  //
                                     // scratch of advance(), kept to allocate nothing per motion
  std::vector<int> open_;
  bool started_ = false;
  long queries_ = 0;
  int pieces_ = 0;  // of the motion being checked (max_pieces)
};

}  // namespace redpost
