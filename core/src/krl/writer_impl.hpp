// The state of a KRL writer (KrlWriter::Impl) and its steps, shared by the writer's sources:
// writer.cpp (the statements and motions), writer_render.cpp (the value of each placeholder)
// and writer_files.cpp (the program files, the parts of a split program, the final renames).
#pragma once

#include <array>
#include <cstdio>
#include <deque>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "krl/writer_templates.hpp"
#include "redpost/io/output_lock.hpp"
#include "redpost/krl/writer.hpp"

namespace redpost {

namespace krl {

// KUKA controllers run on Windows and their own files use CRLF; so does RoboDK. Every line the
// writer emits ends with CRLF, whatever the template file used (docs/krl-templates.md).
inline constexpr std::string_view kEol = "\r\n";

// Parts are numbered NAME_P001 ... with a fixed width, so that they sort by name.
inline constexpr int kMaxParts = 999;
inline constexpr std::string_view kPartInfix = "_P";
inline constexpr size_t kPartSuffixLength = 5;  // "_P001"

// Control characters would break a KRL line; a comment must stay one line. Trailing blanks
// (from a trailing line break) are dropped.
std::string one_line(std::string_view text);

// strerror(errno), for the messages of failed file operations.
std::string errno_text();

}  // namespace krl

struct KrlWriter::Impl {
  KrlTemplateSet t;
  KrlProgramInfo info;
  krl::CompiledTemplates tpl;
  std::string date;  // only if a skeleton asks for {date}

  // Every file made so far, in the order they are renamed: each program's .dat, then its .src;
  // the main program last.
  struct File {
    std::string temp, final_path;
    bool renamed = false;
  };
  OutputLock lock;  // one writer per program name and folder
  std::vector<File> files;
  std::FILE* src_out = nullptr;  // the .src being written
  size_t out_index = 0;          // into files
  std::string module;            // its name
  std::vector<std::string> parts;

  // The byte budget of a .src (docs/krl-templates.md, "Splitting"): the bytes written to the
  // current .src, those of its skeleton after {body}, and, for the first module, those before
  // it (a program that turns out too big becomes NAME_P001, whose header differs).
  long budget = 0;
  long module_bytes = 0;
  long header_bytes = 0;
  long footer_bytes = 0;
  const krl::Skeleton* module_src = nullptr;  // the current .src's skeleton (src, continued_src)

  // Where parts ended (KrlWriter::split()); whether the last motion ended out of the material.
  KrlSplitReport split;
  bool last_in_air = true;
  int last_cl_line = 0;  // of the last motion: where a part that ends now ends

  long motion_count = 0;  // all motions so far
  int motions_in_module = 0;
  bool in_spline = false;
  int spline_points = 0;
  // SPL (docs/krl-templates.md, "SPL segments"): in a spline set with spline_spl and a spline
  // tolerance, the feed move last given is held until the next one shows whether the block
  // passes its end smoothly (an SPL knot) or ends there (a corner); the lines that came after
  // it (comments) wait with it.
  bool spl = false;
  // ... and with spline_lin_vel and spline_spl_vel, a segment whose $VEL.CP differs from the
  // block's carries its own (WITH $VEL.CP): a change of speed no longer ends the block.
  bool segment_vel = false;
  struct PendingSegment {
    KrlMotion motion;                                         // its end
    Eigen::Vector3d start = Eigen::Vector3d::Zero();          // where it starts
    Eigen::Vector3d start_tangent = Eigen::Vector3d::Zero();  // unit at a smooth start, or 0
    double vel = std::numeric_limits<double>::quiet_NaN();    // its own $VEL.CP; NaN: the block's
    long index = 0;                                           // its motion number, 1, 2, ...
    std::vector<std::string> after;
  };
  bool have_pending = false;
  PendingSegment pending;
  Eigen::Vector3d last_p = Eigen::Vector3d::Zero();  // where the last motion ended
  bool joined_smoothly = false;                      // the last feed move's start is a smooth knot
  double vel_in_force = 0.0;                         // the $VEL.CP last written (m/s)
  // Segments written at the motion rate, (motion number, m/s), until asked (take_rate_segment).
  std::deque<std::pair<long, double>> rate_segments;
  double vel_requested = std::numeric_limits<double>::quiet_NaN();
  std::string vel_written;  // the last $VEL.CP statement, to skip repeats
  bool have_last = false;
  AxisValues last_axes;
  int ext_mask = -1;  // external axes (bit n-1 for En) of the first motion
  // The tool: $TOOL's right-hand side and its numbers ($ACT_TOOL, $LOAD) now, and as the
  // current module's header set them.
  struct ToolInForce {
    std::string tool;
    long tool_data = 0, load_data = 0;
  };
  ToolInForce current_tool, header_tool;
  // What a part restates so that it runs alone with the right tool, spindle and coolant.
  std::string tool_state, spindle_state, coolant_state;
  bool src_has_frames = false;  // the src skeleton sets $BASE and $TOOL with {frames}
  bool prepared = false;        // every file complete and flushed, none renamed (prepare())
  bool finished = false;

  // Rendering context: the values of a statement's placeholders (the program's and the
  // module's come from the fields above).
  struct Values {
    const AxisValues* axes = nullptr;
    double xyz[3] = {0, 0, 0};
    KukaAbc abc;
    StatusTurn st;
    double number_value = 0.0;  // vel, rpm, seconds, or an external axis value
    long integer = 0;           // cl line, tool number, axis number
    long tool_data = 0;
    long load_data = 0;
    double aux[3] = {0, 0, 0};  // CIRC auxiliary point
    std::string_view text, tool_name, direction, clockwise, mode, callee, tool, routine;
  };
  std::string_view current;  // the statement or file being rendered, for messages
  std::string line;          // reused buffer
  std::string converted;

  Impl(const KrlTemplateSet& templates, const KrlProgramInfo& program)
      : t(templates),
        info(program),
        current_tool{program.tool, program.tool_data,
                     program.load_data > 0 ? program.load_data : program.tool_data},
        header_tool(current_tool) {}

  // --- rendering (writer_render.cpp) ---------------------------------------------------------
  std::string context() const;
  void number(std::string& out, double v, int decimals, std::string_view what);
  void value(std::string& out, krl::Ph ph, const Values& v);
  void pose_value(std::string& out, krl::Ph ph, const Values& v);
  void axis_value(std::string& out, krl::Ph ph, const Values& v);
  void external_axes(std::string& out, const Values& v);
  void statement_value(std::string& out, krl::Ph ph, const Values& v);
  void program_value(std::string& out, krl::Ph ph);
  void render_into(std::string& out, const krl::Compiled& c, const Values& v);
  std::string render(krl::Stmt s, const Values& v);

  // --- output files (writer_files.cpp) -------------------------------------------------------
  // One logical line; a multi-line statement has '\n' inside. Empty: nothing is written.
  void put(std::FILE* f, size_t file_index, std::string_view text);
  void put(krl::Stmt s, const Values& v) { put(src_out, out_index, render(s, v)); }
  size_t create(const std::string& file_name, std::FILE*& f);
  void close(std::FILE*& f, size_t file_index);
  // Writes skeleton lines [from, to) and returns the index of the block line that stopped it
  // (or to). Defined and used in writer_files.cpp only.
  template <class Block>
  size_t put_skeleton(std::FILE* f, size_t file_index, const krl::Skeleton& sk, size_t from,
                      std::string_view file_kind, Block&& block);
  void write_dat(const std::string& name, const krl::Skeleton& sk, std::string_view kind);
  size_t body_line(const krl::Skeleton& sk) const;
  // A program, or a part; `continued`: a part that continues the cut (continued_src).
  void open_module(const std::string& name, bool continued = false);
  void close_module();
  void next_part(bool continued = false);
  // $BASE and $TOOL for a {frames} line: base_static or base_coupled, then tool_select.
  std::string frames_text(const ToolInForce& tool);
  // A number of the controller's data ({tool_data}, {load_data}, {base_data}), which a set may
  // write only where it is one.
  void data_index(std::string& out, long index, std::string_view what);
  long count_bytes(std::string_view text) const;
  // Starts a new part first if `needed` more bytes would not fit the current .src's budget.
  void ensure_room(long needed);
  // Whether the current part holds three quarters of its budget: it ends at the next place out
  // of the material.
  bool part_nearly_full() const;
  void end_part();  // closes the part (promoting a first module) and starts the next
  void promote_first_module();
  void write_main_program();
  void rename_files();

  // --- statements (writer.cpp) ---------------------------------------------------------------
  void end_spline();
  // The held segment, as SPL when one of its ends is a smooth knot (end_tangent non-zero, or
  // its start's), else as SLIN; then the lines that waited with it.
  void write_pending(const Eigen::Vector3d& end_tangent);
  // A line inside a spline block: after the held segment, if there is one.
  void put_in_block(std::string text);
  void spline_feed_move(const KrlMotion& m);
  void begin_spline();  // $VEL.CP first if it changed, then the block's start
  void ptp_axes(const AxisValues& axes);
  // A PTP from wherever the robot stands (the program's first motion, a part's start): the
  // set's bco_ptp, else ptp_axes.
  void bco_ptp(const AxisValues& axes);
  Values pose_values(const KrlMotion& m);
  void flush_velocity();
  void require_velocity() const;  // a feed move needs a velocity() before it
  // What a new part writes before its first motion; `continued`: only what cannot stop the
  // advance run (the skeleton's frames, or the tool without them).
  void restate(bool continued = false);
};

}  // namespace redpost
