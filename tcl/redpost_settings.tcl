# redpost_settings.tcl: the settings of the redpost NX event handlers (redpost_post.tcl).
#
# Edit this file for your cell; it sits next to redpost_post.tcl, which sources it (or set the
# environment variable REDPOST_SETTINGS to another file). Relative paths are taken relative to
# the directory of this file. Units: mm and degrees. Every setting is the `redpost convert`
# option of the same name (docs/convert.md); docs/nx-integration.md lists them side by side.

namespace eval ::redpost_settings {
    variable dir [file dirname [file normalize [info script]]]

    # Where the redpost Tcl package is: the directory holding pkgIndex.tcl (build/plugin, or
    # <prefix>/lib/redpost0.8.0, or <prefix>/lib). "" : already on auto_path / TCLLIBPATH.
    variable library_dir ""

    # The workcell definition (XML, docs/cell-format.md).
    variable cell [file join $dir .. definitions cells andres2011_kr15_track_table.xml]

    # The KRL template set (docs/krl-templates.md): krc4_lin, krc4_spline, krc2_lin, krc4_circ
    # or a file of your own. "" : the shipped krc4_lin. (--krl)
    variable krl ""

    # Output directory. "" : the directory of NX's output file (mom_output_file_full_name).
    variable output_dir ""

    # Program name: a KRL identifier of at most 24 characters (19 with split). "" : made from
    # the name of NX's output file (mom_output_file_full_name), as `redpost convert` does.
    variable program_name ""

    # Where the CL (workpiece/MCS) frame lies in the cell's base frame {B}: {x y z a b c}
    # (mm, deg, KUKA A-B-C). {} : the CL frame is {B} (the reference cell's table frame).
    variable placement {}

    # Right-hand sides of $BASE = and of $TOOL = before the first tool change. base "" :
    # BASE_DATA[n] of the cell's <controller base-data> (the offset base of a coupled table).
    variable base ""
    variable tool "TOOL_DATA\[1\]"
    # A tool table file (docs/tools.md): CL tool number -> TOOL_DATA index and length. "" : the
    # cell's table, else TOOL_DATA[n] with NX's tool length.
    variable tools ""
    # Clearance height (mm, z of the MCS): above it a rapid may be a PTP. "" : none, every
    # rapid is a straight LIN. Rapids written as LIN move at rapid_vel (m/s).
    variable clearance ""
    variable rapid_vel 0.25
    # Largest .src in bytes: a larger program is split into parts. 0: the template set's
    # <limits>, else 4 MiB.
    variable max_bytes 0

    # $APO.CDIS (mm); motions per file (0: one file); a CL-line comment every N motions;
    # chordal tolerance of circular moves (mm).
    variable apo 0.5
    variable split 0
    variable cl_line_every 50
    variable chordal_tol 0.01

    # A joints log (CSV, one row per motion). "" : none. (--joints-csv)
    variable joints_csv ""

    # An HTML report of the run, written with the program. "" : none. (--report)
    variable report ""

    # What NX's MSYS means: ignore (the MCS is the workpiece frame) or apply (every operation
    # turned into NX's absolute frame by its MCS). (--msys)
    variable msys ignore

    # The redundancy along the path (docs/redundancy.md): plan global or local, preset smooth,
    # stiff or fast, the keyframe spacing (mm), and external axes held: {E1=500 E2}. (--plan,
    # --preset, --keyframe-spacing, --lock)
    variable plan global
    variable preset smooth
    variable keyframe_spacing 20
    variable lock {}

    # The arm's deflection under the cutting force (docs/deflection.md): predict_deflection 1
    # predicts it, compensate 1 also moves every target against it; cutting is the cutting
    # conditions file ("" : the defaults; a file alone asks for the prediction); deflection_tol
    # the tolerance (mm). (--predict-deflection, --compensate, --cutting, --deflection-tol)
    variable predict_deflection 0
    variable compensate 0
    variable cutting ""
    variable deflection_tol 0.05

    # The point reduction (docs/timing.md, "Point reduction"): consecutive cutting points merged
    # into one LIN within fit_tol (mm) of every point dropped and fit_ang_tol (deg) of its tool
    # axis; fit_tol 0 keeps every point. (--fit-tol, --fit-ang-tol)
    variable fit_tol 0.01
    variable fit_ang_tol 0.1

    # Threads that solve the whole-path plan's lattice together (docs/redundancy.md, "Threads"):
    # 1 one thread, 0 one per core (at most 8). The program is the same for any count. (--threads)
    variable threads 1

    # Collisions (docs/collision.md): STL files of the set-up in the MCS (mm), as NX exports
    # them: fixtures {clamp.stl vise.stl}, which nothing moving may come near, and the
    # finished part, which only the cutter may touch; and the least distance kept between
    # bodies (mm). The cell's and the tool's bodies are checked always. (--fixture, --part,
    # --collision-margin)
    variable fixture {}
    variable part ""
    variable collision_margin 5

    # Name used in messages and in the program's header. "" : NX's part (mom_part_name).
    variable source ""

    # 1: put the part name (mom_part_name) in a comment at the start of the program.
    variable part_comment 1
}
