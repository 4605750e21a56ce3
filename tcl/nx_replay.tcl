# nx_replay.tcl: plays an APT/CLSF file through the redpost NX event handlers (redpost_post.tcl)
# the way NX calls them, without NX.
#
#   tclsh tcl/nx_replay.tcl --cell CELL.xml [--krl SET.xml] -o OUTDIR [--name PROG]
#         [--joints-csv FILE] [--placement x,y,z,a,b,c] [--base EXPR] [--tool EXPR] [--apo MM]
#         [--split N] [--cl-line-every N] [--chordal-tol MM] [--msys ignore|apply]
#         [--tools FILE] [--clearance Z] [--rapid-vel M/S] [--max-bytes N] [--lib DIR] [-q] INPUT
#
# The options are those of `redpost convert` (docs/convert.md), and the program is the same, byte
# for byte. --lib DIR puts DIR (the directory of pkgIndex.tcl, e.g. build/plugin) on auto_path.
#
# The file is read through ::redpost::reader_*; each event sets the mom_* variables NX would set
# and calls the MOM_* proc NX would call: MOM_start_of_program, MOM_start_of_path at operation
# starts, MOM_tool_change, MOM_spindle_rpm / MOM_spindle_off, MOM_coolant_on / _off,
# MOM_initial_move (the first motion of the program or after a tool change) or MOM_first_move (the
# first motion of an operation), MOM_rapid_move / MOM_linear_move, MOM_pprint, MOM_insert,
# MOM_end_of_path, MOM_end_of_program. The reader has already linearised arcs and NURBS, so their
# pieces come as MOM_linear_move. Only MOM_output_literal and MOM_output_to_listing_device are
# stubbed. The CL line of every event is given to the session (::redpost_post::source_line,
# which the handlers pass on with ::redpost::set_line), so messages name the file and line as
# `redpost convert` does.
#
# Exit status: 0 when the program was written, 2 on an error (the message on stderr), 1 on a
# usage error.

proc usage {{message ""}} {
    if {$message ne ""} {
        puts stderr "nx_replay: $message"
    }
    puts stderr "usage: tclsh nx_replay.tcl --cell CELL.xml \[--krl SET.xml\] -o OUTDIR\
        \[--name PROG\] \[--joints-csv FILE\] \[--placement x,y,z,a,b,c\] \[--base EXPR\]\
        \[--tool EXPR\] \[--apo MM\] \[--split N\] \[--cl-line-every N\] \[--chordal-tol MM\]\
        \[--msys ignore|apply\] \[--tools FILE\] \[--clearance Z\] \[--rapid-vel M/S\]\
        \[--max-bytes N\] \[--lib DIR\] \[-q\] INPUT"
    exit 1
}

# --- command line -------------------------------------------------------------------------------

array set opt {cell "" krl "" output "" name "" joints-csv "" placement "" base "" tool ""
    apo "" split "" cl-line-every "" chordal-tol "" lib "" quiet 0 msys ignore tools ""
    clearance "" rapid-vel "" max-bytes ""}
set input ""
for {set i 0} {$i < $argc} {incr i} {
    set a [lindex $argv $i]
    switch -- $a {
        --cell - --krl - --name - --joints-csv - --placement - --base - --tool - --apo -
        --split - --cl-line-every - --chordal-tol - --lib - -o - --output - --msys - --tools -
        --clearance - --rapid-vel - --max-bytes {
            if {$i + 1 >= $argc} {
                usage "$a needs a value"
            }
            set key [expr {$a in {-o --output} ? "output" : [string range $a 2 end]}]
            set opt($key) [lindex $argv [incr i]]
        }
        -q - --quiet {
            set opt(quiet) 1
        }
        -h - --help {
            usage
        }
        default {
            if {[string match -* $a] || $input ne ""} {
                usage "unexpected argument '$a'"
            }
            set input $a
        }
    }
}
if {$input eq "" || $opt(cell) eq "" || $opt(output) eq ""} {
    usage "INPUT, --cell and -o are required"
}
if {$opt(lib) ne ""} {
    set auto_path [linsert $auto_path 0 [file normalize $opt(lib)]]
}

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

source [file join [file dirname [file normalize [info script]]] redpost_post.tcl]

namespace eval ::redpost_settings {
    variable cell [file normalize $::opt(cell)]
    # A shipped set's name (no folder, no extension) stays a name.
    variable krl [expr {$::opt(krl) eq "" ||
                        ([file extension $::opt(krl)] eq "" && [string first / $::opt(krl)] < 0)
                        ? $::opt(krl) : [file normalize $::opt(krl)]}]
    variable output_dir [file normalize $::opt(output)]
    variable program_name $::opt(name)
    variable joints_csv [expr {$::opt(joints-csv) eq "" ? "" : [file normalize $::opt(joints-csv)]}]
    # `redpost convert` names the input as it was given, in messages and the header.
    variable source $::input
    variable part_comment 1
    variable placement {}
    variable base ""
    variable tool "TOOL_DATA\[1\]"
    variable tools [expr {$::opt(tools) eq "" ? "" : [file normalize $::opt(tools)]}]
    variable clearance $::opt(clearance)
    variable rapid_vel 0.25
    variable max_bytes 0
    variable apo 0.5
    variable split 0
    variable cl_line_every 50
    variable chordal_tol 0.01
    foreach {key var} {base base tool tool apo apo split split cl-line-every cl_line_every
        chordal-tol chordal_tol rapid-vel rapid_vel max-bytes max_bytes} {
        if {$::opt($key) ne ""} {
            set $var $::opt($key)
        }
    }
    if {$::opt(placement) ne ""} {
        set placement [split $::opt(placement) ,]
        if {[llength $placement] != 6} {
            ::usage "--placement takes six numbers x,y,z,a,b,c (mm and deg),\
                got '$::opt(placement)'"
        }
    }
}

# NX's output file: the program name defaults to it, as convert's defaults to the input's name.
set mom_output_file_full_name [file join $redpost_settings::output_dir \
    [file rootname [file tail $input]].src]
set mom_motion_type ""
set mom_motion_event ""

# --- the replay -----------------------------------------------------------------------------------

proc replay {input} {
    global mom_part_name mom_mcs_goto mom_tool_axis mom_pos mom_motion_type mom_motion_event \
        mom_feed_rate mom_spindle_rpm mom_spindle_speed mom_spindle_direction mom_coolant_mode \
        mom_coolant_status mom_tool_number mom_tool_name mom_tool_diameter mom_tool_length \
        mom_path_name mom_operation_name mom_pprint mom_Instruction
    set reader [::redpost::reader_open $input $::redpost_settings::chordal_tol $::opt(msys)]
    try {
        set started 0
        # The handler for the next motion: NX's initial_move for the first motion of the program
        # and after a tool change, first_move for the first motion of an operation.
        set first MOM_initial_move
        # APT's RAPID applies to the next motion.
        set rapid_next 0
        while {[set e [::redpost::reader_next $reader]] ne ""} {
            set kind [dict get $e kind]
            set text [dict get $e text]
            set ::redpost_post::source_line [dict get $e line]
            if {!$started} {
                set started 1
                if {$kind eq "part_name"} {
                    set mom_part_name $text
                    MOM_start_of_program
                    continue
                }
                MOM_start_of_program
            }
            switch -- $kind {
                part_name {
                    # A PARTNO after the start: NX has no event for it; the same comment.
                    set mom_pprint "part $text"
                    MOM_pprint
                }
                tool_change {
                    set mom_tool_number [dict get $e tool_number]
                    set mom_tool_name $text
                    set mom_tool_diameter [dict get $e tool_diameter_mm]
                    set mom_tool_length [dict get $e tool_length_mm]
                    MOM_tool_change
                    set first MOM_initial_move
                }
                spindle {
                    set mom_spindle_rpm [dict get $e value]
                    set mom_spindle_speed $mom_spindle_rpm
                    set dir [dict get $e direction]
                    set mom_spindle_direction [dict get {CW CLW CCW CCLW OFF NONE} $dir]
                    if {$dir eq "OFF"} {
                        MOM_spindle_off
                    } else {
                        MOM_spindle_rpm
                    }
                }
                feed {
                    # NX has no feed event: the feed is a property of the following motions.
                    set mom_feed_rate [dict get $e value]
                }
                rapid {
                    set rapid_next 1
                }
                move {
                    lassign [dict get $e p] mom_mcs_goto(0) mom_mcs_goto(1) mom_mcs_goto(2)
                    lassign [dict get $e axis] mom_tool_axis(0) mom_tool_axis(1) mom_tool_axis(2)
                    array set mom_pos [array get mom_mcs_goto]
                    set rapid [expr {$rapid_next || [dict get $e rapid]}]
                    set rapid_next 0
                    set mom_motion_type [expr {$rapid ? "RAPID" : "CUT"}]
                    set mom_motion_event [expr {$rapid ? "rapid_move" : "linear_move"}]
                    if {$first ne ""} {
                        $first
                        set first ""
                    } elseif {$rapid} {
                        MOM_rapid_move
                    } else {
                        MOM_linear_move
                    }
                }
                coolant {
                    set mom_coolant_mode $text
                    if {[dict get $e flag]} {
                        set mom_coolant_status ON
                        MOM_coolant_on
                    } else {
                        set mom_coolant_status OFF
                        MOM_coolant_off
                    }
                }
                operation_start {
                    set mom_path_name $text
                    set mom_operation_name $text
                    MOM_start_of_path
                    if {$first ne "MOM_initial_move"} {
                        set first MOM_first_move
                    }
                }
                operation_end {
                    MOM_end_of_path
                }
                comment {
                    set mom_pprint $text
                    MOM_pprint
                }
                literal {
                    # The reader took "KRL:" off; the Insert UDE gives it as the user wrote it.
                    set mom_Instruction "KRL: $text"
                    MOM_insert
                }
                unknown_word - end_of_program - machine_frame - dwell {
                    # MSYS and a cycle's dwell come to NX posts through cycle and MCS events that
                    # the handlers do not take yet (docs/nx-integration.md).
                }
            }
        }
        set ::redpost_post::source_line ""
        if {!$started} {
            MOM_start_of_program
        }
        # The reader's warnings (unknown words, ignored instructions), as convert prints them.
        foreach w [::redpost::reader_warnings $reader] {
            puts stderr "warning: $w"
        }
        MOM_end_of_program
    } finally {
        ::redpost::reader_free $reader
    }
}

if {[catch {replay $input} message]} {
    puts stderr $message
    exit 2
}
exit 0
