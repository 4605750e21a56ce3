// A 3D view of the cell running its program (issue 21): the cell drawn from its DH chain, the
// toolpath on the table coloured by a chosen quantity, and a slider and play button over the
// program's motions. Drawn in the page by three.js (Debian's libjs-three, inlined at build time)
// and the view's own script; HtmlReport::add_scene3d puts both in the report once.
//
// The host streams its motions into a Scene3dRecorder, which keeps a bounded, decimated copy
// (the limits are Scene3dLimits): memory and page size do not grow with the program's length.
// The page redoes the forward kinematics of every kept motion from the DH numbers given here, so
// the view shows what the chain does with the written joints; it also compares its TCP with the
// host's (fkErrorMm() in the page), which the browser test checks.
#pragma once

#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

namespace redpost::report {

// Row-major 3x4: the rotation's rows, each followed by the translation's component (mm).
using Transform34 = std::array<double, 12>;
Transform34 identity34();

// One joint of the chain. Standard DH: Rz(theta) Tz(d) Tx(a) Rx(alpha); modified: Rx(alpha)
// Tx(a) Rz(theta) Tz(d). A revolute or virtual joint adds q to theta, a prismatic one to d.
struct SceneLink {
  enum class Type { revolute, prismatic, virtual_spin };
  std::string name;
  std::string axis;  // "A1".."E6", "none"
  Type type = Type::revolute;
  bool modified_dh = false;
  double alpha_rad = 0.0, a_mm = 0.0, theta_rad = 0.0, d_mm = 0.0;
  Transform34 T_prev_link = identity34();  // a fixed transform before the link
  double lower = 0.0, upper = 0.0;         // limits, DH units (rad, mm)
  // Controller value = sign * q + offset (deg or mm); sign 0: no controller axis.
  double axis_sign = 0.0, axis_offset = 0.0;
};

// The chain {B} -> T_B_0 -> links -> T_last_tcp -> TCP, and the workpiece frame in {B}.
struct SceneCell {
  std::string name;
  std::vector<SceneLink> links;
  Transform34 T_B_0 = identity34();
  Transform34 T_last_tcp = identity34();
  Transform34 T_B_part = identity34();
  double reference_tool_length_mm = std::numeric_limits<double>::quiet_NaN();
  // The first `positioner_joints` joints carry the workpiece (a turntable): the floor is the
  // frame after them, and the table with the toolpath turns in it. 0: {B} is the floor.
  int positioner_joints = 0;
};

// A quantity the toolpath can be coloured by, one value per motion (NaN: none there).
struct SceneQuantity {
  std::string name;  // "1/kappa_F"
  std::string unit;  // "" or "%", "mm"
  bool higher_is_better = true;
  double threshold = std::numeric_limits<double>::quiet_NaN();  // drawn on the colour bar
  std::string threshold_name;                                   // "switch threshold"
  // A label rather than a measure (a plane's number): neither end is better, and thinning keeps
  // the first value of the points it merges.
  bool categorical = false;
};

// At most this many joints and quantities (the C ABI's rp_motion carries 16 joints).
inline constexpr int kSceneMaxJoints = 16;
inline constexpr int kSceneMaxQuantities = 6;

struct Scene3dLimits {
  int max_frames = 2000;                // motions the slider steps through
  std::size_t max_path_points = 50000;  // points of the drawn toolpath
};

// One motion as the host reports it. Pointers are read during add() only.
struct SceneMotion {
  long index = 0;  // 1, 2, ... in program order
  int cl_line = 0;
  const double* q = nullptr;  // joint_count values, DH units (rad, mm), chain order
  int joint_count = 0;
  double tool_length_mm = std::numeric_limits<double>::quiet_NaN();
  double tcp_shift_mm = 0.0;  // the tool's TCP beyond the chain's, along -z of its TCP frame
  double tcp_part_mm[3] = {0.0, 0.0, 0.0};  // the host's TCP in the workpiece frame
  const double* values = nullptr;           // one per quantity
};

// A translucent rectangle in the workpiece frame (a measurement plane, say): a corner and its
// two edges (mm).
struct SceneRect {
  std::array<double, 3> corner{}, edge_u{}, edge_v{};
  std::string colour = "#1f77b4";
  std::string name;
};

// A body of the collision check (docs/collision.md), drawn translucent with the cell: its shapes
// in the frame it moves with.
struct SceneShape {
  std::string kind;              // "sphere", "capsule", "cylinder", "box", "mesh"
  Transform34 T = identity34();  // in the body's frame; capsule and cylinder along z, centred
  double radius_mm = 0.0, length_mm = 0.0;
  std::array<double, 3> size_mm{};       // box: edge lengths
  std::vector<float> vertices;           // mesh: x y z per vertex (mm)
  std::vector<std::uint32_t> triangles;  // mesh: three vertex indices per triangle
};
struct SceneBody {
  std::string name;
  std::string role;  // "cell", "tool", "fixture", "part": the colour
  int frame = -1;    // a link's index (the frame after it), -1 the cell's {B}, -2 the TCP
  std::vector<SceneShape> shapes;
};
// A mesh of more triangles is drawn as its box, so that the page stays small.
inline constexpr std::size_t kSceneMaxMeshTriangles = 20000;

// The closest approach of two bodies along the program: a line between the two nearest points
// (in the workpiece frame), marked in the view.
struct SceneClosest {
  bool shown = false;
  std::array<double, 3> a{}, b{};
  std::string label;  // "16.8 mm, arm_link_5 vs fixture clamp_tower.stl, motion 48"
};

// What the page gets: the cell, the kept motions and the thinned toolpath.
struct Scene3d {
  SceneCell cell;
  std::vector<SceneQuantity> quantities;
  // Kept motions: per frame, one value per link (cell.links), then tool length, TCP shift and
  // the TCP's x y z.
  std::vector<float> frame_data;
  std::vector<std::uint32_t> frame_motion;  // motion index
  std::vector<std::uint32_t> frame_line;    // CL line
  // The toolpath in the workpiece frame: x y z per point, the motion index of each point, and
  // per quantity one byte per point (0..254 over [lo, hi], 255: none).
  std::vector<float> path_xyz;
  std::vector<std::uint32_t> path_motion;
  std::vector<std::vector<std::uint8_t>> path_value_codes;
  std::vector<std::array<double, 2>> value_range;  // per quantity: lo, hi
  // Set by the host after scene(): the path as separate points (measurement points) rather
  // than a line, and rectangles on the table.
  bool path_as_points = false;
  std::vector<SceneRect> rects;
  std::string path_name = "toolpath";  // what the path is, for the page's labels
  // Set by the host after scene(): the bodies of the collision check, and the closest approach.
  std::vector<SceneBody> bodies;
  SceneClosest closest;
  std::string line_label = "CL line";  // what frame_line counts, for the readout
  // How the data were decimated, for the page's note.
  long motions = 0;
  long frame_stride = 1;           // every n-th motion (and the last) is a frame
  double path_tolerance_mm = 0.0;  // points closer than this to the last kept one are merged
  Scene3dLimits limits;

  long frames() const { return static_cast<long>(frame_motion.size()); }
  long path_points() const { return static_cast<long>(path_motion.size()); }
};

// Streams motions into a Scene3d within the limits. Frames: every motion until max_frames are
// kept, then the stride doubles and every second kept frame is dropped (so the kept ones stay
// evenly spread), and the last motion is always kept. Toolpath: a point closer than the
// tolerance to the last kept one is merged into it, keeping the worse value of each quantity
// (the lower where higher is better), so a bad spot stays visible; when the path outgrows
// max_path_points the tolerance doubles and the path is thinned again. O(limits) memory.
class Scene3dRecorder {
 public:
  Scene3dRecorder(SceneCell cell, std::vector<SceneQuantity> quantities, Scene3dLimits limits = {});

  // Throws std::invalid_argument when the motion's joint count differs from the cell's. Allocates
  // nothing once the frame and path buffers have grown to their limits.
  void add(const SceneMotion& m);

  long motions() const { return motions_; }
  // The scene for the page. Quantities with no value anywhere are left out.
  Scene3d scene() const;

 private:
  // Joints, then tool length, TCP shift and the TCP (the page's frame layout).
  struct Frame {
    std::array<float, kSceneMaxJoints + 5> data{};
    std::uint32_t motion = 0, line = 0;
  };
  struct PathPoint {
    float p[3];
    std::uint32_t motion;
    std::array<float, kSceneMaxQuantities> values;
  };
  void add_path_point(const SceneMotion& m);
  void merge_values(PathPoint& into, const PathPoint& from) const;
  void rethin();
  Frame frame_of(const SceneMotion& m) const;

  SceneCell cell_;
  std::vector<SceneQuantity> quantities_;
  Scene3dLimits limits_;
  long motions_ = 0;
  long stride_ = 1;
  std::vector<Frame> frames_;
  Frame last_;
  std::vector<PathPoint> path_;
  double tol_mm_ = 0.001;
};

}  // namespace redpost::report
