# nx_replay.tcl: plays an APT/CLSF file through the redpost NX event handlers (redpost_post.tcl)
# the way NX's postprocessor calls them, without NX.
#
#   tclsh tcl/nx_replay.tcl --cell CELL.xml -o OUTDIR [the options of redpost convert]
#         [--lib DIR] [--post POST.tcl] [-q] INPUT
#
# The options are those of `redpost convert` (docs/convert.md), and the program, the joints log
# and the report are the same, byte for byte. --lib DIR puts DIR (the directory of pkgIndex.tcl,
# e.g. build/plugin) on auto_path. --post POST.tcl plays the file through a post made by
# scripts/make_nx_post.sh instead, with the post's settings (the options given replace them).
#
# The replay is a small NX of its own: it reads the CL file record by record (its own reading,
# not redpost's CL reader) and, as NX's postprocessor does for the toolpath the file stands for,
# sets the mom_* variables of each event and calls its MOM_* proc, in NX's order
# (shared/evaldata/nx-tcl/HANDLERS.md): MOM_start_of_program; per TOOL PATH MOM_start_of_path,
# MOM_msys, MOM_first_tool or MOM_tool_change with MOM_load_tool, MOM_spindle_rpm,
# MOM_coolant_on, MOM_cutcom_on, MOM_initial_move (the first motion of the program and after a
# tool change) or MOM_first_move (of an operation), then MOM_before_motion and one of
# MOM_rapid_move, MOM_linear_move, MOM_circular_move (CIRCLE with its GOTO), MOM_nurbs_move
# (NURBS with its KNOT and CNTRL records), MOM_from_move; a drilling cycle as MOM_drill /
# MOM_drill_dwell / MOM_drill_deep / MOM_drill_break_chip, a MOM_drill_move per hole and
# MOM_cycle_off; MOM_pprint, MOM_insert, MOM_end_of_path, MOM_end_of_program. What NX would
# compute the replay computes as the CL file says it: a feed per revolution in mm/min, a GODLTA's
# point, the units. The CL line of every event is given to the session
# (::redpost_post::source_line), so messages name the file and line as `redpost convert` does,
# and what the file says that NX never would (an unknown word, no UNITS record) is warned of
# in convert's words (::redpost_post::warn). Only MOM_output_literal and
# MOM_output_to_listing_device are stubbed.
#
# Exit status: 0 when the program was written, 2 on an error (the message on stderr), 1 on a
# usage error.

set here [file dirname [file normalize [info script]]]
source [file join $here nx_replay_options.tcl]

# --- NX's built-in commands: the two the handlers use for output ---------------------------------

proc MOM_output_to_listing_device {text} {
    if {!$::opt(quiet)} {
        puts stdout $text
    }
}
proc MOM_output_literal {text} {
    puts stdout $text
}

# --- the handlers, with the settings from the command line --------------------------------------

# --post POST.tcl: a post's event handler file (scripts/make_nx_post.sh), as NX would source it.
source [expr {[info exists opt(post)] ? $opt(post) : [file join $here redpost_post.tcl]}]
replay_settings

# NX's output file: the program name defaults to it, as convert's defaults to the input's name.
set mom_output_file_full_name [file join $redpost_settings::output_dir \
    [file rootname [file tail $input]].src]
set mom_output_unit MM
set mom_motion_type ""
set mom_motion_event ""

source [file join $here nx_replay_cl.tcl]

if {[catch {::nx_replay::run $input} message]} {
    puts stderr $message
    exit 2
}
exit 0
