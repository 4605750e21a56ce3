/* redpost.h: the C ABI of libredpost, the one boundary every host uses (the redpost command,
 * the Tcl package and NX event handlers, any C/C++/Python host).
 *
 * A session turns the events of a toolpath into a KUKA KRL program: open it with the cell, the
 * template set, the output directory and the program name; send the events in order; close it,
 * which writes the program and renames the files into place. The same events give the same bytes
 * whichever host sends them.
 *
 * Rules:
 * - Every call returns an rp_status. RP_OK is 0. On any other status, rp_last_error(session)
 *   gives the message, with the event index ("event 1204: part.apt:1180: pose ... unreachable").
 *   No C++ exception ever crosses this boundary.
 * - A NULL session is RP_ERR_NULL. Events before rp_open succeeded or after rp_close are
 *   RP_ERR_STATE. After an error inside an event the session is failed: later events return
 *   RP_ERR_STATE, and closing it writes nothing (it removes every temporary file).
 * - rp_free releases a session (open, closed or failed). Using a session after rp_free is
 *   undefined, like any use after free.
 * - Threads: a session must be used by one thread at a time. Different sessions on different
 *   threads are independent and may run concurrently. rp_last_error(NULL) is per thread.
 * - Units: mm, degrees for placement angles, mm/min for feeds, rpm. Coordinates are in the CL
 *   (workpiece) frame; tool axes point from the tool tip towards the spindle.
 *
 * The header compiles as C99 and as C++.
 */
#ifndef REDPOST_H
#define REDPOST_H

#ifdef __cplusplus
extern "C" {
#endif

#define REDPOST_VERSION_MAJOR 0
#define REDPOST_VERSION_MINOR 8
#define REDPOST_VERSION_PATCH 0
#define REDPOST_VERSION "0.8.0"

#if defined(REDPOST_BUILDING_LIBRARY)
#define RP_API __attribute__((visibility("default")))
#else
#define RP_API
#endif

typedef enum rp_status {
  RP_OK = 0,
  RP_ERR_BAD_INPUT = 1,   /* a malformed value, file contents, NaN, a zero tool axis */
  RP_ERR_IO = 2,          /* a file that cannot be read or written */
  RP_ERR_UNREACHABLE = 3, /* a pose the cell cannot reach (or a joint jump) */
  RP_ERR_JOINT_LIMIT = 4, /* a pose only reachable beyond a joint limit */
  RP_ERR_STATE = 5,       /* a call out of order: before open, after close, after a failure */
  RP_ERR_NULL = 6,        /* a NULL session or a NULL required argument */
  RP_ERR_INTERNAL = 7     /* a bug in redpost */
} rp_status;

typedef struct rp_session rp_session;

typedef struct rp_options {
  unsigned struct_size;        /* sizeof(rp_options), set by rp_options_init */
  const char* cell_path;       /* required: the cell definition (XML) */
  const char* krl_path;        /* template set: a file, or a shipped set's name (krc4_lin,
                                  krc4_spline, krc2_lin, krc4_circ); NULL: krc4_lin */
  const char* output_dir;      /* required, must exist */
  const char* program_name;    /* required: KRL identifier, at most 24 characters */
  const char* joints_csv_path; /* NULL: none */
  const char* source_name;     /* name used in messages, e.g. the CL file; NULL: "<events>" */
  const char* base;            /* right-hand side of $BASE =; NULL: "BASE_DATA[1]" */
  const char* tool;            /* right-hand side of $TOOL =; NULL: "TOOL_DATA[1]" */
  int has_placement;           /* 1: placement is used */
  double placement[6];         /* x, y, z (mm), a, b, c (deg): the CL frame in the cell's {B} */
  double apo_mm;               /* $APO.CDIS; default 0.5 */
  int motions_per_file;        /* 0: no splitting */
  int cl_line_every;           /* a CL line comment every N motions; default 50 */
  double chordal_tolerance_mm; /* for circular moves; default 0.01 */
  /* Added in 0.2 (hosts built against 0.1 get the defaults). */
  const char* tools_path;        /* a tool table file (docs/tools.md); NULL: the cell's */
  int has_clearance;             /* 1: clearance_z_mm is the clearance plane of rapids */
  double clearance_z_mm;         /* z in the CL frame above which a rapid may be a PTP */
  double rapid_velocity_m_per_s; /* $VEL.CP of rapids written as LIN; default 0.25 */
  long max_file_bytes;           /* largest .src; 0: the template set's, or 512 KiB */
  /* Added in 0.3: the redundancy along the path (docs/redundancy.md, "Whole-path planning").
   * Hosts built against 0.2 get the defaults, so the plan is global for them too. */
  int plan;                   /* RP_PLAN_GLOBAL (default) or RP_PLAN_LOCAL (Algorithm 1 alone) */
  int plan_preset;            /* RP_PLAN_SMOOTH (default), RP_PLAN_STIFF or RP_PLAN_FAST */
  double keyframe_spacing_mm; /* path between the plan's keyframes; default 20 */
  unsigned lock_mask;         /* bit k set: external axis E(k+1) is held (not planned); bits
                                 6 and up refused (RP_ERR_BAD_INPUT) */
  double lock_value[6];       /* E1..E6 (mm, deg) for a held axis (global plan only); NaN:
                                 where the first pose puts it */
  /* Added in 0.4: the arm's deflection under the cutting forces (docs/deflection.md). The cell
   * needs the joint stiffness of its six arm joints; hosts built against 0.3 get it off. */
  int deflection;                 /* RP_DEFLECTION_OFF (default), _PREDICT or _COMPENSATE */
  const char* cutting_path;       /* the cutting conditions file; NULL: the defaults */
  double deflection_tolerance_mm; /* the normal deflection is judged against it; default 0.05 */
  /* Added in 0.6: what NX's MSYS (rp_machine_frame, RP_EVENT_MSYS) means, and the report. */
  int msys;                /* RP_MSYS_IGNORE (default) or RP_MSYS_APPLY (rp_msys_mode below) */
  const char* report_path; /* an HTML report of the run (docs/reports.md), written with the
                              program (rp_prepare, renamed into place by rp_close); NULL: none */
  /* 1: the events are tracked on a thread of the session's own while the host makes the next
   * ones (the same program, byte for byte). An event's error then comes from a later call (the
   * next event, rp_prepare or rp_close) with that event's message; queries wait for every event
   * sent; the motion observer is called on the session's thread. Default 0. */
  int pipeline;
  /* Added in 0.8: the point reduction (docs/timing.md, "Point reduction"). Consecutive cutting
   * points are merged into one LIN where it stays within fit_tolerance_mm of every point it
   * drops and within fit_angle_tolerance_deg of its tool axis. 0: every point kept, the program
   * of 0.7. Defaults 0.01 mm and 0.1 deg; a host built against 0.7 (a struct_size without
   * these fields) gets 0, its program unchanged. */
  double fit_tolerance_mm;
  double fit_angle_tolerance_deg;
  /* Appended after the point reduction: threads that solve the whole-path plan's lattice
   * nodes together (docs/redundancy.md, "Threads"). 1 (the default): the calling thread alone;
   * 0: one per core, at most 8. The program is the same, byte for byte, for any count. */
  int plan_threads;
  /* Appended after plan_threads: collisions (docs/collision.md). The cell's own bodies (its
   * <collision>) and the tool's (the tool table's geometry, else the CL file's diameter) are
   * checked along every motion; a motion that brings two bodies closer than the margin is
   * refused (RP_ERR_UNREACHABLE, the CL line, the two bodies, the distance). A host built
   * against an older rp_options gets the check with the default margin and no set-up. */
  const char* const* fixture_paths; /* STL files of fixtures, in the CL frame, mm; NULL: none */
  int fixture_count;                /* entries of fixture_paths */
  const char* part_path;            /* STL of the finished part, in the CL frame; NULL: none */
  double collision_margin_mm;       /* least distance kept between bodies; default 5, 0 to 1000 */
  int collision_check;              /* 1 (default): check; 0: no body is checked */
} rp_options;

enum { RP_PLAN_GLOBAL = 0, RP_PLAN_LOCAL = 1 };
/* OFF: no model. PREDICT: the tool's deflection at every cutting move, the program unchanged.
 * COMPENSATE: each cutting target moved against the deflection until the deflected tool lands
 * on the CL point (a fixed point per move). */
enum { RP_DEFLECTION_OFF = 0, RP_DEFLECTION_PREDICT = 1, RP_DEFLECTION_COMPENSATE = 2 };
enum { RP_PLAN_SMOOTH = 0, RP_PLAN_STIFF = 1, RP_PLAN_FAST = 2 };

typedef enum rp_spindle_direction {
  RP_SPINDLE_OFF = 0,
  RP_SPINDLE_CW = 1,
  RP_SPINDLE_CCW = 2
} rp_spindle_direction;

/* Diagnostics of the last tracked pose. */
typedef struct rp_move_info {
  int joint_count;
  double joints[16];    /* DH units: rad and mm, chain order, the virtual joint included */
  double axes[12];      /* controller values A1..A6, E1..E6 (deg, mm); NaN if not mapped */
  double inv_condition; /* 1/kappa_F of the arm */
  int iterations;
  double position_error_mm;
  double orientation_error_rad;
  double limit_margin; /* smallest distance to a limit, fraction of that joint's range */
} rp_move_info;

typedef struct rp_summary {
  long poses;   /* postures tracked */
  long motions; /* motions written */
  double lowest_inv_condition;
  int lowest_inv_condition_line;
  int warnings; /* number of warnings (see rp_warning) */
} rp_summary;

/* The library's version, e.g. "0.6.0". */
RP_API const char* rp_version(void);

/* Fills *options with the defaults. Call before setting fields. */
RP_API void rp_options_init(rp_options* options);

/* Opens a session. On failure *session is set to NULL and rp_last_error(NULL) says why. */
RP_API rp_status rp_open(const rp_options* options, rp_session** session);

/* The line (or event index) of the events that follow, for messages and the joints log. The
 * session counts events itself; hosts that read a file set the file's line. 0: the events'
 * own numbers again; a negative line is refused (RP_ERR_BAD_INPUT, the session goes on). */
RP_API rp_status rp_set_line(rp_session* session, int line);

/* A tool change to tool `number` of the cell's tool table. diameter_mm and length_mm are the CL
 * file's (the tool's collision bodies where the table gives none): the diameter 0 to 500 mm or
 * NaN for not given, the length 0 to 2000 mm; anything else fails the session. */
RP_API rp_status rp_tool_change(rp_session* session, int number, const char* name,
                                double diameter_mm, double length_mm);
RP_API rp_status rp_spindle(rp_session* session, double rpm, rp_spindle_direction direction);
RP_API rp_status rp_feed(rp_session* session, double mm_per_min);
/* The next move is a rapid traverse. */
RP_API rp_status rp_rapid(rp_session* session);
/* A straight move to (x, y, z) with the tool axis (i, j, k) (normalised here; zero refused). */
RP_API rp_status rp_linear_move(rp_session* session, double x, double y, double z, double i,
                                double j, double k);
/* An arc from the current point to (x, y, z) about the axis (ax, ay, az) through the centre
 * (cx, cy, cz), turning by the right-hand rule about the axis (as APT's CIRCLE followed by its
 * GOTO), with the tool axis (i, j, k) at the end. The axis need not be unit (normalised here;
 * zero refused). radius_mm is the CL file's radius, a check and nothing more: 0 when not given,
 * else the start point's distance from the axis must equal it within the arc point tolerance,
 * and a negative one is refused (RP_ERR_BAD_INPUT, by this call). The arc's radius is always the
 * start point's distance from the axis; the end must lie on that circle. A change of height
 * along the axis makes a helix. Linearised within the chordal tolerance. Every coordinate must
 * be finite and within 1e7 mm. */
RP_API rp_status rp_circular_move(rp_session* session, double cx, double cy, double cz, double ax,
                                  double ay, double az, double radius_mm, double x, double y,
                                  double z, double i, double j, double k);
RP_API rp_status rp_operation_start(rp_session* session, const char* name);
RP_API rp_status rp_operation_end(rp_session* session);
/* Coolant on (on != 0) or off. mode: the CL file's word (FLOOD, MIST, ...; NULL: none), named in
 * the program's comment and nothing else: any text. */
RP_API rp_status rp_coolant(rp_session* session, int on, const char* mode);
/* A comment in the program (sanitised to one line). */
RP_API rp_status rp_comment(rp_session* session, const char* text);
/* A literal line passed to the program as it is. */
RP_API rp_status rp_literal(rp_session* session, const char* text);

/* --- Added in 0.6: the rest of the toolpath (docs/nx-integration.md, "The events") ----------
 * What a CL file says beyond moves, so that every front end (a CL file through the reader, NX's
 * postprocessor, any host) gives the session the same events and gets the same program. */

/* A drilling cycle (CYCLE/DRILL..., NX's MOM_drill, MOM_drill_deep, ...): lengths in mm along
 * the tool axis from a hole's point, its top. NaN where the cycle gives none. */
typedef struct rp_cycle_params {
  unsigned struct_size; /* sizeof(rp_cycle_params), set by rp_cycle_params_init */
  int peck;             /* 1: a pecking (deep) cycle, full retract to the clearance between pecks */
  double depth_mm;      /* FEDTO: the hole's bottom below its point (required) */
  double clearance_mm;  /* RAPTO: rapids stop this far above the point (required) */
  double retract_mm;    /* RTRCTO: where the tool goes after the hole; NaN: the clearance */
  double feed_mm_per_min; /* the cycle's feed; NaN: the feed in force (rp_feed) */
  double dwell_s;         /* at the hole's bottom, 0 to 600 s; default 0 */
  double first_peck_mm;   /* 1STPECK (required for a pecking cycle deeper than 0) */
  double next_peck_mm;    /* SUBPECK; NaN: first_peck_mm */
  const char* name; /* for messages, e.g. "CYCLE/DRILL" or "MOM_drill_deep"; NULL: CYCLE/DRILL */
} rp_cycle_params;
RP_API void rp_cycle_params_init(rp_cycle_params* params);
/* Defines the cycle and switches it on: every move (rp_linear_move, like a GOTO in a CL file) or
 * rp_cycle_hole until rp_cycle_off is a hole of it, written as its rapid, feed, peck, dwell and
 * retract moves. A tool change or an operation start while it is on interrupts it: a motion
 * after that, before rp_cycle_off, is refused (it cannot be told a hole or a move). */
RP_API rp_status rp_cycle_define(rp_session* session, const rp_cycle_params* params);
/* A hole of the cycle at (x, y, z), its point on the surface, with the tool axis (i, j, k). */
RP_API rp_status rp_cycle_hole(rp_session* session, double x, double y, double z, double i,
                               double j, double k);
/* CYCLE/ON: the last cycle defined on again. */
RP_API rp_status rp_cycle_on(rp_session* session);
RP_API rp_status rp_cycle_off(rp_session* session);
/* A NURBS from the current point (NURBS/ with KNOT/ and CNTRL/, NX's MOM_nurbs_move): knots
 * as given, non-decreasing, either the complete clamped vector (with or without the current
 * point as the first control point) or the NX CLSF form without the end knots
 * (docs/cl-format.md, "NURBS"); points are x, y, z (mm) and the weight (> 0) of each control
 * point, 4 doubles each. The tool axis (i, j, k) holds along it. Split into chords within the
 * chordal tolerance. */
RP_API rp_status rp_nurbs_move(rp_session* session, const double* knots, int knot_count,
                               const double* points, int point_count, double i, double j, double k);
/* NX's MSYS / MOM_msys: the MCS's origin and its X and Y axes (unit, orthogonal) in NX's
 * absolute frame. Under RP_MSYS_IGNORE every MSYS must be the same (the MCS is the workpiece
 * frame); under RP_MSYS_APPLY the points and vectors after it are turned into the absolute frame.
 * The arrays hold 3 doubles each. */
RP_API rp_status rp_machine_frame(rp_session* session, const double* origin, const double* x_axis,
                                  const double* y_axis);
/* A dwell (NX's MOM_delay), 0 to 600 s. */
RP_API rp_status rp_dwell(rp_session* session, double seconds);
/* Cutter radius compensation on (side "LEFT", "RIGHT" or "ON") or off: KRL has none, so a warning
 * says that the points are taken as the tool centre. side is named in that warning and nothing
 * else (any text, NULL: none). */
RP_API rp_status rp_cutcom(rp_session* session, int on, const char* side);
typedef enum rp_text_kind {
  RP_TEXT_INSERT = 0, /* INSERT/, NX's Insert: a comment, or "KRL: statement" as code */
  RP_TEXT_PPRINT = 1, /* PPRINT/, NX's MOM_pprint: a comment */
  RP_TEXT_MESSAGE = 2 /* NX's operator message: a comment, without a warning */
} rp_text_kind;
/* Operator text, as the CL file or NX gives it; each written as a comment with a warning that
 * names its line (up to 20), but INSERT's "KRL: statement", which passes the (checked) statement
 * through as rp_literal does. */
RP_API rp_status rp_operator_text(rp_session* session, rp_text_kind kind, const char* text);
/* A warning of the host's own (about its input: an unknown CL word, ...): listed before the
 * session's own by rp_warning and in the report. Taken until rp_prepare. */
RP_API rp_status rp_warn(rp_session* session, const char* text);

/* Added in 0.3.2. Completes the program and the joints log and flushes them to the disk,
 * without renaming anything: every check has run and a full disk has shown. The session then
 * takes no more events, but its queries (rp_summary_get, rp_timing_get, rp_warning, ...) work,
 * so a host can write its own files (a report) before the program replaces an old one of the
 * same name. rp_close renames the files; rp_free without rp_close removes them. Optional:
 * rp_close alone does both steps. */
RP_API rp_status rp_prepare(rp_session* session);
/* Writes the program (rp_prepare, if not done) and renames the files into place, as one swap:
 * if a file cannot be renamed in, an old program of the same name is put back whole. The
 * session stays allocated, closed. */
RP_API rp_status rp_close(rp_session* session);
/* Added in 0.3.2. Removes every temporary file (and program lock file) of this process that
 * was not yet renamed into place. Async-signal-safe: a host's SIGTERM/SIGINT handler may call
 * it before the process ends. A program's swap under way (its files renamed in) is waited for
 * (at most 5 s), and from this call on no session of the process creates or swaps in another
 * file: a thread that would waits for the process to end. redpost also removes the temporaries
 * at exit(). */
RP_API void rp_remove_temporaries(void);
/* Releases the session. A session that was not closed is abandoned: nothing is written. */
RP_API void rp_free(rp_session* session);

/* The message of the last error of this session, or of this thread's last rp_open when
 * session is NULL. Never NULL; "" when there was none. Valid until the next call on it. */
RP_API const char* rp_last_error(const rp_session* session);

/* Added in 0.6: the CL line (rp_set_line) or event number that the last error of this session
 * names, 0 when it names none. Under the whole-path plan a motion is tracked some events after
 * it was sent, so the line may be an earlier event's than the call that failed. */
RP_API int rp_last_error_line(const rp_session* session);

/* Added in 0.8: waits until every event sent has been tracked (a session opened with
 * rp_options.pipeline tracks them on its own thread; without it, at once) and returns the status
 * of an event that failed there, the session then failed with that event's message
 * (rp_last_error) and line, or RP_OK. A host that stops sending for a reason of its own (its
 * input is broken further on) calls it to tell an earlier event's failure first, as a session
 * without the pipeline would have. */
RP_API rp_status rp_sync(rp_session* session);

RP_API rp_status rp_last_move(const rp_session* session, rp_move_info* info);
RP_API rp_status rp_summary_get(const rp_session* session, rp_summary* summary);
/* The range a joint used over the poses tracked so far, as `redpost convert` prints it. */
typedef struct rp_joint_range_info {
  const char* name;      /* the joint's name in the cell; valid while the session lives */
  const char* axis_name; /* "A1".."A6", "E1".."E6", or "none" (a static string) */
  int prismatic;         /* 1: values in mm; 0: in degrees */
  /* Lowest and highest value used, in controller units (deg, mm) where the joint has an axis
   * (a negative sign swaps the ends), DH degrees or mm otherwise; +inf/-inf before any pose. */
  double lowest, highest;
  /* Smallest distance to the limit at the lowest / highest end, in the same units. */
  double margin_lower, margin_upper;
} rp_joint_range_info;

/* Joint number index (0-based, chain order, the virtual joint included) of the session's cell.
 * RP_ERR_BAD_INPUT past the last joint (a host may count the joints so). Added for the summary
 * table of `redpost convert`. */
RP_API rp_status rp_joint_range(const rp_session* session, int index, rp_joint_range_info* range);

/* --- Watching the motions as they are written ------------------------------------------------ */

typedef enum rp_motion_kind {
  RP_MOTION_PTP = 0,   /* PTP to a full E6AXIS (the first motion) */
  RP_MOTION_RAPID = 1, /* a rapid traverse */
  RP_MOTION_LIN = 2    /* a cutting move at the feed */
} rp_motion_kind;

/* One written motion. struct_size is sizeof(rp_motion) of the library that calls: a host built
 * against an older, shorter rp_motion reads its own fields only; newer fields go at the end. */
typedef struct rp_motion {
  unsigned struct_size;
  long index; /* 1, 2, ... in the order written (the joints CSV's "pose" column) */
  rp_motion_kind kind;
  int line; /* the CL line (rp_set_line) or event index of the motion */
  int joint_count;
  double joints[16];    /* DH units: rad and mm, chain order, the virtual joint included */
  double axes[12];      /* controller values A1..A6, E1..E6 (deg, mm); NaN if not mapped */
  double inv_condition; /* 1/kappa_F of the arm at the written posture */
  /* The tracker's switch threshold on 1/kappa_F (the same for every motion of a session). */
  double conditioning_threshold;
  int iterations;         /* of the solve of the written posture */
  double feed_mm_per_min; /* the feed in force for RP_MOTION_LIN; NaN for PTP and rapid */
  double tcp[3];          /* the TCP in the CL (workpiece) frame, mm */
  /* Added in 0.3 (docs/timing.md): the time model. The observer is called once the motion is
   * timed: at the next stop, or when later motions can no longer change it, which may be 64 or
   * more motions later (and, for the last ones, during rp_close). */
  double time_s;       /* when the motion ends, from the program's start */
  double duration_s;   /* how long it takes */
  double speed_mm_s;   /* the highest path speed it reaches (0 for PTP) */
  double asked_mm_s;   /* the speed asked: the CL feed or the rapid speed; NaN for PTP */
  double command_mm_s; /* the $VEL.CP written (lower where an axis limits it); NaN for PTP */
  const char* limit;   /* what kept it below the asked speed ("none", "axis velocity", ...) */
  int limit_joint;     /* the joint behind it (chain index), -1 */
  /* Per joint, the largest fraction of its velocity limit it reaches (0: no limit known). */
  double speed_fraction[16];
  /* Appended in 0.3.1: the whole-path plan's posture the tracker followed at this motion
   * (DH units, chain order) where planned is 1; planned 0 where none was (RP_PLAN_LOCAL, a
   * stretch tracked pose by pose, PTP motions). */
  int planned;
  double planned_joints[16];
  /* Appended in 0.4 (docs/deflection.md): the tool's deflection under the cutting force at this
   * motion, at the posture written; has_deflection 0 where none was predicted (no model, a
   * rapid, a PTP, a plunge, a drilling cycle, the spindle off, a step inside a longer move). */
  int has_deflection;
  double deflection_mm[3];           /* of the TCP, CL frame */
  double deflection_rotation_rad[3]; /* small rotation vector, CL frame */
  double deflection_normal_mm;       /* along the machined wall's normal: + cuts too deep */
  double cutting_force_N;            /* the mean cutting force's magnitude */
  double compensation_mm;            /* how far the target was moved (0 without compensation) */
  double residual_mm;                /* the model's error left at the written posture */
  double residual_normal_mm;         /* ... along the wall's normal */
  int compensation_iterations;       /* of the fixed point (0 without compensation) */
  /* Appended in 0.5 (docs/reports.md, the 3D view): the tool in force at this motion. */
  double tool_length_mm; /* from the spindle's gauge line to the tip; NaN: unknown */
  double tcp_shift_mm;   /* its TCP beyond the chain's TCP (rp_cell_info), along -z of that frame */
  /* Appended with the collision check (docs/collision.md): the least distance computed between
   * two bodies that may not touch on this motion (at its end and wherever the check looked
   * closer; mm, +inf where no pair came within reach of the margin, NaN where nothing is
   * checked), its pair ("" if none), and where clearance_exact is 1 its nearest points in the CL
   * frame; and the proven lower bound of every distance along the motion. */
  double clearance_mm;
  double clearance_proven_mm;
  const char* clearance_pair; /* "spindle vs fixture vise.stl"; valid during the call */
  int clearance_exact;
  double clearance_point_a[3], clearance_point_b[3];
} rp_motion;

/* Called once per written motion, once it is timed, on the thread that sent an event. The
 * pointer is valid during the call only. It must return normally (no longjmp, no C++ exception)
 * and must not call back into the session. */
typedef void (*rp_motion_observer)(const rp_motion* motion, void* user);

/* Sets (fn != NULL) or removes (fn == NULL) the session's motion observer; user is passed back.
 * Only on an open session (RP_ERR_STATE otherwise). Motions written before and already timed
 * are not replayed; those written before but not yet timed are reported to it.
 * Without an observer nothing is computed for it. Added for `redpost convert --report`. */
RP_API rp_status rp_set_motion_observer(rp_session* session, rp_motion_observer fn, void* user);

/* The time model of the program (docs/timing.md), complete after rp_close. Added in 0.3. */
typedef struct rp_timing {
  unsigned struct_size;       /* set to sizeof(rp_timing) before the call */
  double cycle_time_s;        /* every motion and dwell; tool changes take no time in it */
  double cutting_time_s;      /* the motions at a CL feed, as the controller runs them */
  double feed_time_s;         /* the same motions at exactly the CL feed */
  int axis_speeds_known;      /* 1: the cell gives its axes' speeds; 0: they limit nothing */
  long slowed_motions;        /* motions written with a $VEL.CP below the asked speed */
  double peak_speed_fraction; /* the largest fraction of a velocity limit any axis reaches */
  int peak_speed_joint;       /* its joint (chain index), -1 */
  int peak_speed_line;        /* its CL line */
  long feed_limits;           /* stretches where an axis keeps the feed 5 % or more lower */
  int feed_limits_listed;     /* how many of them rp_feed_limit gives (the first 1000) */
  int untimed_tool_changes;   /* tool changes (HALT, a routine) whose own time is not known */
  /* Appended in 0.3.1: the whole-path plan (RP_PLAN_GLOBAL; all 0 under RP_PLAN_LOCAL). */
  long plan_windows;          /* windows planned */
  long plan_fallback_windows; /* of them, tracked pose by pose (no sequence on the lattice) */
  long plan_ik_evaluations;   /* lattice nodes solved, one closed-form IK posture each */
  /* Appended in 0.7: the controller's clock (docs/timing.md, "The interpolation cycle"). */
  double interpolation_cycle_s;   /* the template set's IPO cycle (0.012 on a KR C4) */
  long cp_motions;                /* CP motions timed (LIN, CIRC, SLIN) */
  long below_cycle_motions;       /* of them, lasting less than one cycle at their $VEL.CP */
  long rate_limited_motions;      /* kept slow by the motion rate (one per cycle): below a
                                     cycle, or (0.8) written at it (rate_slowed_motions) */
  long lookahead_limited_motions; /* of them, slowed by the look-ahead ($ADVANCE) */
  double shortest_motion_s;       /* the shortest CP motion at its $VEL.CP (0: none) */
  int shortest_motion_line;       /* its CL line */
  /* Appended in 0.8: the point reduction (rp_options.fit_tolerance_mm). */
  long reducible_points;    /* cutting points it could merge (after a cut, within one feed) */
  long reduced_moves;       /* the moves tracked for them (both 0 without the reduction) */
  long rate_slowed_motions; /* with the reduction: motions written with the $VEL.CP at which
                               they last one interpolation cycle (they would last less) */
  long reduced_arcs;        /* of reduced_moves, arcs fitted through the points (a set with
                               CIRC; each a CIRC where it is proven, else its chords) */
  /* Appended in 0.8 (issue 47): of plan_windows, those planned with the external axes held
     (where the window started, or where a fresh window's approach puts them), since that was
     faster than moving them or conditioned the arm better (docs/redundancy.md). */
  long plan_still_windows;
} rp_timing;
RP_API rp_status rp_timing_get(const rp_session* session, rp_timing* timing);

/* Stretch number index (0-based) where one axis keeps the feed below the CL file's. */
typedef struct rp_feed_limit_info {
  unsigned struct_size;      /* set to sizeof(rp_feed_limit_info) before the call */
  int first_line, last_line; /* CL lines */
  long motions;
  int joint; /* chain index; -1 for "motion rate", "look-ahead" (0.7) and "curvature" (0.8) */
  const char* joint_name; /* valid while the session lives; "" when joint is -1 */
  const char* axis_name;  /* "A1".."E6" or "none" (static); "-" when joint is -1 */
  /* "axis velocity", "axis acceleration", "corner", and since 0.7 "motion rate" (motions
     shorter than one interpolation cycle) and "look-ahead" ($ADVANCE too short to stop in), and
     since 0.8 "curvature" (a CIRC whose radius keeps it below the feed at $ACC.CP). */
  const char* limit;
  double lowest_mm_per_min; /* the lowest speed reached on it */
  double asked_mm_per_min;  /* the feed asked */
} rp_feed_limit_info;
/* RP_ERR_BAD_INPUT past the last one listed. */
RP_API rp_status rp_feed_limit(const rp_session* session, int index, rp_feed_limit_info* info);

/* The deflection of the program (docs/deflection.md), complete after rp_prepare. Added in 0.4. */
typedef struct rp_deflection_summary {
  unsigned struct_size;         /* set to sizeof(rp_deflection_summary) before the call */
  int mode;                     /* RP_DEFLECTION_OFF, _PREDICT or _COMPENSATE */
  double tolerance_mm;          /* what the normal deflection was judged against */
  int operations;               /* entries rp_deflection_get gives: CL operations with a load */
  long unloaded_moves;          /* cutting moves without a modelled load (plunges, spindle off) */
  long compensation_iterations; /* fixed-point iterations beyond the first, whole program */
  int max_compensation_iterations; /* the most one move needed */
} rp_deflection_summary;
RP_API rp_status rp_deflection_summary_get(const rp_session* session,
                                           rp_deflection_summary* summary);

/* The deflection over CL operation number index (0-based, in program order). */
typedef struct rp_deflection_info {
  unsigned struct_size;  /* set to sizeof(rp_deflection_info) before the call */
  const char* operation; /* its name ("" before any); valid while the session lives */
  int first_line, last_line;
  long motions;                        /* cutting moves with a load */
  double max_mm, rms_mm;               /* |deflection of the TCP| */
  double max_normal_mm, rms_normal_mm; /* |its component along the wall's normal| */
  int max_normal_line;                 /* the CL line of the largest */
  double max_rotation_rad;
  double max_force_N;
  long over_tolerance;    /* motions whose normal component passes the tolerance */
  double max_residual_mm; /* after compensation (without it: the deflection) */
  double max_residual_normal_mm;
  long over_tolerance_after;
  double max_compensation_mm; /* the longest move of a target */
} rp_deflection_info;
/* RP_ERR_BAD_INPUT past the last one. */
RP_API rp_status rp_deflection_get(const rp_session* session, int index, rp_deflection_info* info);

/* The collision check of the program (docs/collision.md), complete after rp_prepare. Appended
 * with the collision check. */
typedef struct rp_collision_summary {
  unsigned struct_size; /* set to sizeof(rp_collision_summary) before the call */
  int checked;          /* 1: some pair of bodies was checked */
  int bodies, pairs;    /* of the last scene (the last tool's) */
  double margin_mm;
  /* The least distance computed between two bodies along the program (mm; +inf where no pair
   * came within reach of the margin), its CL line and pair ("" if none; valid while the session
   * lives). */
  double least_clearance_mm;
  int least_clearance_line;
  const char* least_clearance_pair;
  long distance_queries;      /* distances computed */
  double proven_clearance_mm; /* the least proven lower bound along the program */
} rp_collision_summary;
RP_API rp_status rp_collision_get(const rp_session* session, rp_collision_summary* summary);

/* --- The cell's model, for a host that draws it (added in 0.5) ------------------------------- */

/* Rigid transforms are 12 doubles, row-major 3x4: the rotation's rows, each followed by the
 * translation's component (mm). */
typedef enum rp_joint_type {
  RP_JOINT_REVOLUTE = 0,
  RP_JOINT_PRISMATIC = 1,
  RP_JOINT_VIRTUAL = 2 /* the tool's free spin: revolute, never sent to a controller */
} rp_joint_type;

/* The session's cell as a chain (docs/conventions.md): {B} -> T_B_0 -> link 0 -> ... -> link n-1
 * -> T_last_tcp -> the chain's TCP. The workpiece (CL) frame is T_B_part in {B}. */
typedef struct rp_cell_info {
  unsigned struct_size; /* set to sizeof(rp_cell_info) before the call */
  int joint_count;
  double T_B_0[12];
  double T_last_tcp[12];
  double T_B_part[12];
  double reference_tool_length_mm; /* the tool length the chain's TCP stands for; NaN: none */
  int coupled_base_joint;          /* chain index of the turntable that carries the base; -1 */
  int robroot_joint;               /* chain index of the track that carries the robot; -1 */
} rp_cell_info;
RP_API rp_status rp_cell_info_get(const rp_session* session, rp_cell_info* info);

/* Link number index (0-based, chain order). Standard DH: Rz(theta) Tz(d) Tx(a) Rx(alpha);
 * modified: Rx(alpha) Tx(a) Rz(theta) Tz(d); a revolute (virtual) joint adds q to theta, a
 * prismatic one to d; T_prev_link comes before the link. RP_ERR_BAD_INPUT past the last. */
typedef struct rp_link_info {
  unsigned struct_size;  /* set to sizeof(rp_link_info) before the call */
  const char* name;      /* valid while the session lives */
  const char* axis_name; /* "A1".."A6", "E1".."E6", or "none" (a static string) */
  rp_joint_type type;
  int modified_dh; /* 1: modified (Khalil-Kleinfinger), 0: standard */
  double alpha_rad, a_mm, theta_rad, d_mm;
  double T_prev_link[12]; /* the identity when the chain gives no fixed transform */
  double lower, upper;    /* joint limits, DH units (rad, mm) */
  /* The controller value is axis_sign * q + axis_offset (q in deg or mm); 0 and 0 without an
   * axis. */
  double axis_sign, axis_offset;
} rp_link_info;
RP_API rp_status rp_link_get(const rp_session* session, int index, rp_link_info* info);

/* Warning number index (0-based) of the session, or NULL past the end: the host's (rp_warn)
 * first, then the session's own. */
RP_API const char* rp_warning(const rp_session* session, int index);
/* The final path of written .src file number index (0: the main program), or NULL. */
RP_API const char* rp_output_file(const rp_session* session, int index);

/* --- Reading CL files (APT/CLDATA, NX CLSF), for hosts that replay a file -------------------- */

typedef struct rp_reader rp_reader;

typedef enum rp_event_kind {
  RP_EVENT_PART_NAME = 0,
  RP_EVENT_TOOL_CHANGE,
  RP_EVENT_SPINDLE,
  RP_EVENT_FEED,
  RP_EVENT_RAPID,
  RP_EVENT_MOVE,
  RP_EVENT_COOLANT,
  RP_EVENT_OPERATION_START,
  RP_EVENT_OPERATION_END,
  RP_EVENT_COMMENT,
  RP_EVENT_LITERAL,
  RP_EVENT_UNKNOWN_WORD,
  RP_EVENT_END_OF_PROGRAM,
  RP_EVENT_DWELL,         /* value = seconds at a hole's bottom (added in 0.2) */
  RP_EVENT_MACHINE_FRAME, /* NX MSYS: p = origin, axis = MCS z, flag = applied (added in 0.2) */
  RP_EVENT_ARC, /* CIRCLE + GOTO (rp_reader_options.arcs_as_events): p, axis the end; arc_centre,
                   arc_axis (right-hand rule); value the radius, 0: from the start (added in 0.2) */
  /* Added in 0.6: the toolpath events of a reader opened with toolpath_events, for the session
   * to expand (rp_session_event) as it expands the calls above. */
  RP_EVENT_CYCLE,         /* cycle defined and on: `cycle`, text its name (rp_cycle_define) */
  RP_EVENT_CYCLE_ON,      /* CYCLE/ON */
  RP_EVENT_CYCLE_OFF,     /* CYCLE/OFF */
  RP_EVENT_HOLE,          /* a hole at p with the tool axis `axis` (rp_cycle_hole) */
  RP_EVENT_NURBS,         /* nurbs_knots, nurbs_points, axis (rp_nurbs_move); rapid */
  RP_EVENT_MSYS,          /* p the origin, msys_x, msys_y (rp_machine_frame) */
  RP_EVENT_OPERATOR_TEXT, /* text, text_kind (rp_operator_text) */
  RP_EVENT_CUTCOM,        /* flag on, text the side (rp_cutcom) */
  RP_EVENT_FROM,          /* FROM/: a move like RP_EVENT_MOVE, refused while a cycle is on */
  RP_EVENT_GODLTA         /* GODLTA: by p (flag 0) or by value along axis (flag 1) from where the
                             tool is; axis the tool axis; refused while a cycle is on */
} rp_event_kind;

typedef struct rp_event {
  rp_event_kind kind;
  int line;        /* line of the record in the CL file */
  double p[3];     /* move: x, y, z (mm) */
  double axis[3];  /* move: tool axis (unit) */
  int rapid;       /* move: a rapid traverse */
  int tool_number; /* tool change */
  double tool_diameter_mm, tool_length_mm;
  double value; /* spindle rpm, feed mm/min */
  rp_spindle_direction direction;
  int flag;         /* coolant on; machine frame applied */
  const char* text; /* names, comments, literals; valid until the next rp_reader_next */
  /* Added in 0.2: a drilling cycle's clearance plane for its moves (through clearance_p,
   * normal to the move's tool axis). */
  int has_clearance;
  double clearance_p[3];
  double arc_centre[3];
  double arc_axis[3];
  /* Added in 0.6, written only by a reader opened with toolpath_events and read by
   * rp_session_event only for the kinds added in 0.6 (so a host built against 0.5 is safe). */
  rp_cycle_params cycle;
  const double* nurbs_knots; /* valid until the next rp_reader_next */
  int nurbs_knot_count;
  const double* nurbs_points; /* x, y, z, w per control point */
  int nurbs_point_count;
  double msys_x[3], msys_y[3];
  rp_text_kind text_kind;
} rp_event;

typedef enum rp_msys_mode {
  RP_MSYS_IGNORE = 0, /* NX's MCS is the workpiece frame (default) */
  RP_MSYS_APPLY = 1   /* CL data turned into NX's absolute frame by each MSYS */
} rp_msys_mode;

typedef struct rp_reader_options {
  unsigned struct_size; /* sizeof(rp_reader_options), set by rp_reader_options_init */
  double chordal_tolerance_mm;
  rp_msys_mode msys;
  int arcs_as_events; /* non-zero: CIRCLE + GOTO as one RP_EVENT_ARC (a session may write a
                         CIRC) */
  /* Added in 0.6. Non-zero: the toolpath events as the file gives them (drilling cycles and holes,
   * NURBS, MSYS, operator text, CUTCOM, FROM, GODLTA; arcs whole), for rp_session_event to
   * expand in the session, as NX's events are; msys and arcs_as_events are then not used (the
   * session's rp_options.msys is). 0: plain events, expanded by the reader. */
  int toolpath_events;
} rp_reader_options;

RP_API void rp_reader_options_init(rp_reader_options* options);

/* Opens a CL file. On failure *reader is NULL and rp_last_error(NULL) says why. */
RP_API rp_status rp_reader_open(const char* path, double chordal_tolerance_mm, rp_reader** reader);
/* The same with all reader options. */
RP_API rp_status rp_reader_open_ex(const char* path, const rp_reader_options* options,
                                   rp_reader** reader);
/* The next event: RP_OK and *more = 1, or RP_OK and *more = 0 at the end; an error otherwise
 * (rp_reader_last_error gives "file:line:column: ..."). */
RP_API rp_status rp_reader_next(rp_reader* reader, rp_event* event, int* more);
RP_API const char* rp_reader_last_error(const rp_reader* reader);
/* Warning number index of the reader (unknown words), or NULL past the end. */
RP_API const char* rp_reader_warning(const rp_reader* reader, int index);
RP_API void rp_reader_free(rp_reader* reader);

/* Sends one reader event to a session (what `redpost convert` does for every event). It is
 * refused as the call of the same event would be (a kind that is no rp_event_kind, a NaN, a zero
 * axis, a negative radius, a cycle's struct_size, NULL NURBS arrays, ...), its message and
 * rp_last_error_line naming the event's own line. */
RP_API rp_status rp_session_event(rp_session* session, const rp_event* event);

#ifdef __cplusplus
}
#endif

#endif /* REDPOST_H */
