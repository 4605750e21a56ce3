# redpost_post.tcl: NX Post (MOM) event handlers that stream the toolpath into redpost and write
# a KUKA KRL program (.src/.dat) for a redundant robotic milling cell.
#
# Source this file from the event handler file of an NX postprocessor (docs/nx-integration.md).
# It reads its settings from redpost_settings.tcl next to it (or $env(REDPOST_SETTINGS)), loads
# the redpost Tcl package and defines the MOM_* procs below. Every event becomes one call of the
# C ABI session (redpost.h) through the ::redpost:: commands: the session expands drilling
# cycles, NURBS and NX's MSYS exactly as it does for a CL file, so NX gives the same KRL, byte for
# byte, as `redpost convert` on the same toolpath with the same options.
#
# Variables read (NX's names; docs/nx-integration.md lists them per event): mom_mcs_goto(0..2)
# and mom_tool_axis(0..2) for every motion (MCS, not machine coordinates: the robot's kinematics
# is redpost's job), mom_motion_type, mom_motion_event, mom_feed_rate (mm/min), the arc's
# mom_arc_center / mom_pos_arc_center, mom_arc_axis, mom_arc_direction, mom_arc_radius, the
# NURBS's mom_nurbs_knots/_knot_count/_points/_point_count, the cycles' mom_cycle_*, the MCS's
# mom_msys_origin / mom_msys_matrix, mom_csys_matrix, the tool's mom_tool_number / _name /
# _diameter / _length, mom_spindle_rpm / _speed / _direction / _mode, mom_coolant_mode,
# mom_cutcom_mode, mom_delay_value / _mode / _revs, mom_pprint, mom_operator_message,
# mom_Instruction, mom_path_name / mom_operation_name, mom_part_name, mom_output_unit,
# mom_output_file_full_name.
#
# Messages go to MOM_output_to_listing_device (NX's information window) when that command
# exists, to stdout otherwise. An error of the plugin (an unreachable pose, a joint limit, bad
# input) abandons the program (nothing is written) and aborts the postprocess: MOM_abort with the
# operation, the event and the reason in NX, a Tcl error elsewhere.

namespace eval ::redpost_post {
    variable here [file dirname [file normalize [info script]]]
    # The session handle of the program being written ("" : none).
    variable session ""
    # Set by hosts that replay a CL file (nx_replay.tcl): replaying 1, and the CL line of the
    # event being handled, passed to the session with it. In NX the handlers number the events.
    variable replaying 0
    variable source_line ""
    # Events handled since MOM_start_of_program, and the line the session was last given.
    variable seq 0
    variable line_sent ""
    # The feed last given to the session (mm/min), so that it is sent when it changes.
    variable feed_sent ""
    # The operation and the tool of the events: for messages, and so that MOM_load_tool after
    # MOM_tool_change changes nothing.
    variable operation ""
    variable operations {}
    variable tool_changed ""
    # A drilling cycle is on (MOM_drill* ... MOM_cycle_off).
    variable cycle_on 0
    # Where the events changed name: {line name line name ...} (the last 8192), so that an error
    # of an event the plan tracked some events later is told with its own event.
    variable event_runs {}
    variable last_event ""
}

# Settings first: they say where the package is. A post's event handler file names its own
# (::redpost_settings_file, scripts/make_nx_post.sh), else $env(REDPOST_SETTINGS), else the file
# next to this one.
if {[info exists ::redpost_settings_file] && $::redpost_settings_file ne ""} {
    source $::redpost_settings_file
} elseif {[info exists ::env(REDPOST_SETTINGS)] && $::env(REDPOST_SETTINGS) ne ""} {
    source $::env(REDPOST_SETTINGS)
} else {
    source [file join $::redpost_post::here redpost_settings.tcl]
}
if {$::redpost_settings::library_dir ne ""} {
    set ::redpost_post::libdir [file join $::redpost_settings::dir $::redpost_settings::library_dir]
    if {[lsearch -exact $::auto_path $::redpost_post::libdir] < 0} {
        set ::auto_path [linsert $::auto_path 0 $::redpost_post::libdir]
    }
}
# Not on auto_path: try the install layout (<prefix>/share/redpost/tcl -> <prefix>/lib*) and the
# source tree's build directory.
if {[catch {package require redpost}]} {
    foreach ::redpost_post::libdir [concat \
            [glob -nocomplain -directory [file join $::redpost_post::here .. .. ..] lib*] \
            [list [file join $::redpost_post::here .. build plugin]]] {
        set ::redpost_post::libdir [file normalize $::redpost_post::libdir]
        if {[lsearch -exact $::auto_path $::redpost_post::libdir] < 0} {
            lappend ::auto_path $::redpost_post::libdir
        }
    }
    package require redpost
}

source [file join $::redpost_post::here redpost_post_options.tcl]

namespace eval ::redpost_post {

    # A message for the user: NX's listing device, or stdout.
    proc tell {text} {
        if {[llength [info commands ::MOM_output_to_listing_device]]} {
            ::MOM_output_to_listing_device $text
        } else {
            puts stdout $text
        }
    }

    # The operation the event of `line` belongs to ("" before any).
    proc operation_of {line} {
        variable operations
        set name ""
        foreach {first op} $operations {
            if {$first > $line} {
                break
            }
            set name $op
        }
        return $name
    }

    # Stops the postprocess after an error in the event $event: the session is abandoned (no
    # file is written) and the user sees the operation, the event and the reason. `line` is the
    # line (CL line or event number) the error names: under the whole-path plan a motion is
    # tracked some events after it came, and the message is about that one.
    proc abort {event message {code {REDPOST ERROR}} {line 0}} {
        variable session
        variable seq
        variable operation
        if {$session ne ""} {
            catch {::redpost::free $session}
            set session ""
        }
        set where $event
        set op $operation
        if {[string is integer -strict $line] && $line > 0} {
            set op [operation_of $line]
            set name [event_at $line]
            if {$name ne "" && $name ne $event} {
                set where "$name (reported at $event)"
            }
        }
        # The ABI counts the calls ("event 1204: "); the line says more: the CL line (replayed)
        # or the event's number in the run (NX).
        regsub {^event [0-9]+: } $message "" message
        set text "redpost: $where"
        if {$op ne ""} {
            append text " in operation $op"
        }
        if {!$::redpost_post::replaying && [string is integer -strict $line] && $line > 0} {
            append text " (event $line of the run)"
        }
        append text ": $message"
        if {[llength [info commands ::MOM_abort]]} {
            tell $text
            ::MOM_abort $text
        }
        return -code error -errorcode [lrange $code 0 1] $text
    }

    # The event that had `line` (from event_runs; the first of those that share it), "" if it
    # is too far back.
    proc event_at {line} {
        variable event_runs
        set name ""
        foreach {first n} $event_runs {
            if {$first > $line || ($first == $line && $name ne "" && $at == $line)} {
                break
            }
            set name $n
            set at $first
        }
        return $name
    }

    # The event `event` at `line`: noted where the name changes.
    proc note_event {line event} {
        variable event_runs
        variable last_event
        lappend event_runs $line $event
        set last_event $event
        if {[llength $event_runs] > 16384} {
            set event_runs [lrange $event_runs end-8191 end]
        }
    }

    # The line of the event being handled: the CL line when a CL file is replayed, else the
    # event's number in the run.
    proc line {} {
        variable replaying
        variable source_line
        variable seq
        return [expr {$replaying ? $source_line : $seq}]
    }

    # A failed call of the session for the event $event: the program is abandoned.
    proc failed {event message options} {
        set code [dict get $options -errorcode]
        abort $event $message $code [lindex $code 2]
    }

    # One call of the session for the event $event: ::redpost::$command session args..., the
    # session given the event's line first.
    proc send {event command args} {
        variable session
        variable line_sent
        variable last_event
        if {$session eq ""} {
            abort $event "no redpost program is open (MOM_start_of_program did not run or failed)"
        }
        set line [line]
        if {$event ne $last_event} {
            note_event $line $event
        }
        if {[catch {
            if {$line ne $line_sent} {
                ::redpost::set_line $session $line
                set line_sent $line
            }
            ::redpost::$command $session {*}$args
        } message options]} {
            failed $event $message $options
        }
    }

    # A value of a mom_ variable (global scalar or array element), or $default.
    proc mom {name {default ""}} {
        upvar #0 $name v
        if {[info exists v]} {
            return $v
        }
        return $default
    }

    # x y z of a mom_ array such as mom_mcs_goto.
    proc vec {name {default {0 0 0}}} {
        upvar #0 $name v
        if {[array exists v]} {
            set out {}
            foreach k {0 1 2} d $default {
                lappend out [expr {[info exists v($k)] ? $v($k) : $d}]
            }
            return $out
        }
        return $default
    }

    # The next event: counted, for its number in messages.
    proc next_event {} {
        variable seq
        incr seq
    }

    # NX has no feed event: mom_feed_rate holds the feed of each motion (on rapids, the traverse
    # rate, which is not sent). Sent before a feed motion when it changed.
    proc feed_for {event} {
        variable feed_sent
        upvar #0 mom_feed_rate feed
        if {[info exists feed] && $feed ne $feed_sent && [string is double -strict $feed] &&
                $feed > 0} {
            send $event feed $feed
            set feed_sent $feed
        }
    }

    # A motion to mom_mcs_goto with mom_tool_axis: a rapid traverse or a feed move. Inside a
    # drilling cycle a motion that is not a hole of it (NX sends those as MOM_drill_move) is sent
    # with the cycle off, so that the session does not take it for a hole.
    proc motion {event rapid} {
        variable cycle_on
        variable session
        variable line_sent
        variable last_event
        global mom_mcs_goto mom_tool_axis
        if {$cycle_on} {
            send $event cycle_off
        }
        if {$rapid} {
            send $event rapid
        } else {
            feed_for $event
        }
        if {$session eq ""} {
            abort $event "no redpost program is open (MOM_start_of_program did not run or failed)"
        }
        # The one call of most events: the line goes with the move.
        set line [line]
        if {$event ne $last_event} {
            note_event $line $event
        }
        if {![array exists mom_tool_axis]} {
            array set mom_tool_axis {0 0 1 0 2 1}
        }
        if {[catch {::redpost::linear_move $session $mom_mcs_goto(0) $mom_mcs_goto(1) \
                        $mom_mcs_goto(2) $mom_tool_axis(0) $mom_tool_axis(1) $mom_tool_axis(2) \
                        $line} message options]} {
            failed $event $message $options
        }
        set line_sent $line
        if {$cycle_on} {
            send $event cycle_on
        }
    }

    # The first motion of a path (MOM_initial_move, MOM_first_move): NX calls it instead of the
    # motion's own event, which mom_motion_event names (rapid_move, linear_move, circular_move,
    # nurbs_move, a cycle's drill_move, ...); else mom_motion_type RAPID says a rapid.
    proc first_motion {event} {
        set kind [mom mom_motion_event]
        switch -glob -- $kind {
            circular_move - helix_move {
                circular $event
            }
            nurbs_move {
                nurbs $event
            }
            *_move {
                if {[string match drill* $kind] || [string match bore* $kind] ||
                        [string match tap* $kind]} {
                    hole $event
                } else {
                    motion $event [expr {$kind eq "rapid_move"}]
                }
            }
            default {
                motion $event [expr {[mom mom_motion_type] eq "RAPID"}]
            }
        }
    }

    # An arc (or a helix) about mom_arc_axis through the centre: mom_arc_center (MCS, like
    # mom_mcs_goto) when NX provides it, mom_pos_arc_center otherwise. mom_arc_direction CLW
    # means clockwise looking down the axis, i.e. negative about it by the right-hand rule that
    # the session follows, so the axis is reversed for it. mom_arc_radius 0 or absent: from the
    # start point.
    proc circular {event} {
        if {[mom mom_motion_type] eq "RAPID"} {
            send $event rapid
        } else {
            feed_for $event
        }
        if {[array exists ::mom_arc_center]} {
            set centre [vec mom_arc_center]
        } else {
            set centre [vec mom_pos_arc_center]
        }
        set axis [vec mom_arc_axis [vec mom_tool_axis {0 0 1}]]
        if {[string toupper [mom mom_arc_direction CCLW]] in {CLW CW}} {
            set axis [lmap c $axis {expr {-$c}}]
        }
        send $event circular_move {*}$centre {*}$axis [mom mom_arc_radius 0] \
            {*}[vec mom_mcs_goto] {*}[vec mom_tool_axis {0 0 1}]
    }

    # A NURBS from the current point: mom_nurbs_knots(0..knot_count-1) and the control points
    # mom_nurbs_points(i,0..2) with the weight mom_nurbs_points(i,3) where NX gives one (1
    # otherwise); the session takes the complete knot vector or NX's CLSF form.
    proc nurbs {event} {
        global mom_nurbs_knots mom_nurbs_points
        if {[mom mom_motion_type] eq "RAPID"} {
            send $event rapid
        } else {
            feed_for $event
        }
        set knots {}
        for {set k 0} {$k < [mom mom_nurbs_knot_count 0]} {incr k} {
            lappend knots $mom_nurbs_knots($k)
        }
        set points {}
        for {set k 0} {$k < [mom mom_nurbs_point_count 0]} {incr k} {
            lappend points $mom_nurbs_points($k,0) $mom_nurbs_points($k,1) \
                $mom_nurbs_points($k,2) \
                [expr {[info exists mom_nurbs_points($k,3)] ? $mom_nurbs_points($k,3) : 1}]
        }
        send $event nurbs_move $knots $points {*}[vec mom_tool_axis {0 0 1}]
    }

    # A drilling cycle (MOM_drill, MOM_drill_dwell, MOM_drill_deep, MOM_drill_break_chip):
    # mom_cycle_feed_to is the depth from the hole's top (NX gives it negative into the part;
    # its size is taken), mom_cycle_rapid_to the clearance and mom_cycle_retract_to the retract
    # height above the top, mom_cycle_feed_rate the feed (mm/min), mom_cycle_delay the dwell (s)
    # and, when pecking, mom_cycle_step1 / step2 the first and the next pecks.
    proc cycle {event peck} {
        variable cycle_on
        set depth [mom mom_cycle_feed_to]
        if {[string is double -strict $depth]} {
            set depth [expr {abs($depth)}]
        }
        # Named in messages as NX's CLSF writes these cycles.
        set args [list -peck $peck -depth $depth -clearance [mom mom_cycle_rapid_to] \
                      -retract [mom mom_cycle_retract_to] -name CYCLE/DRILL]
        set feed [mom mom_cycle_feed_rate]
        if {[string is double -strict $feed] && $feed > 0} {
            lappend args -feed $feed
        }
        set dwell 0
        if {[string toupper [mom mom_cycle_delay_mode SECONDS]] eq "REVS"} {
            set revs [mom mom_cycle_delay_revs 0]
            set rpm [mom mom_spindle_rpm 0]
            if {$revs > 0 && $rpm > 0} {
                set dwell [expr {60.0 * $revs / $rpm}]
            }
        } else {
            set dwell [mom mom_cycle_delay 0]
        }
        lappend args -dwell $dwell
        if {$peck} {
            foreach {option var} {-first-peck mom_cycle_step1 -next-peck mom_cycle_step2} {
                set v [mom $var]
                if {[string is double -strict $v] && $v > 0} {
                    lappend args $option $v
                }
            }
        }
        send $event cycle {*}$args
        set cycle_on 1
    }

    # A hole of the cycle at mom_mcs_goto (its top) along mom_tool_axis.
    proc hole {event} {
        send $event cycle_hole {*}[vec mom_mcs_goto] {*}[vec mom_tool_axis {0 0 1}]
    }

    # A tool change, once per tool between two MOM_start_of_path (NX sends MOM_tool_change or
    # MOM_first_tool, then MOM_load_tool for the same tool).
    proc tool_change {event} {
        variable tool_changed
        variable cycle_on
        # A cycle still on is interrupted (the session refuses motion until it is off).
        set cycle_on 0
        set number [mom mom_tool_number 0]
        send $event tool_change $number [mom mom_tool_name] [mom mom_tool_diameter 0] \
            [mom mom_tool_length 0]
        set tool_changed $number
    }
}

# --- program ------------------------------------------------------------------------------------

proc MOM_start_of_program {} {
    set ns ::redpost_post
    if {[set ${ns}::session] ne ""} {
        catch {::redpost::free [set ${ns}::session]}
        set ${ns}::session ""
    }
    foreach {var value} {seq 0 line_sent "" feed_sent "" operation "" operations {}
        tool_changed "" cycle_on 0 event_runs {} last_event ""} {
        set ${ns}::$var $value
    }
    ${ns}::next_event
    if {[catch {${ns}::open_options} opts]} {
        ${ns}::abort MOM_start_of_program $opts
    }
    if {[catch {::redpost::open {*}$opts} s options]} {
        ${ns}::abort MOM_start_of_program $s [dict get $options -errorcode]
    }
    set ${ns}::session $s
    ${ns}::tell "redpost [::redpost::version]: writing [dict get $opts -name] to\
                 [dict get $opts -output]"
    if {$::redpost_settings::part_comment && [${ns}::mom mom_part_name] ne ""} {
        ${ns}::send MOM_start_of_program comment "part [${ns}::mom mom_part_name]"
    }
}

proc MOM_end_of_program {} {
    set ns ::redpost_post
    ${ns}::next_event
    ${ns}::send MOM_end_of_program close
    set s [set ${ns}::session]
    foreach w [::redpost::warnings $s] {
        ${ns}::tell "redpost warning: $w"
    }
    set sum [::redpost::summary $s]
    ${ns}::tell "redpost: poses [dict get $sum poses] (motions written [dict get $sum motions]),\
                 lowest 1/kappa_F of the arm [format %.3f [dict get $sum lowest_inv_condition]]"
    foreach f [dict get $sum files] {
        ${ns}::tell "redpost: wrote $f"
    }
    ::redpost::free $s
    set ${ns}::session ""
}

# A warning of the host about its input (nx_replay.tcl: an unknown CL word), listed with the
# session's and in the report.
proc ::redpost_post::warn {text} {
    send host warn $text
}

# --- operations, coordinate systems and tools ---------------------------------------------------

proc MOM_start_of_path {} {
    set ns ::redpost_post
    ${ns}::next_event
    set name [${ns}::mom mom_path_name [${ns}::mom mom_operation_name]]
    set ${ns}::operation $name
    lappend ${ns}::operations [${ns}::line] $name
    set ${ns}::tool_changed ""
    set ${ns}::cycle_on 0
    ${ns}::send MOM_start_of_path operation_start $name
}

proc MOM_end_of_path {} {
    ::redpost_post::next_event
    ::redpost_post::send MOM_end_of_path operation_end
}

# The operation's MCS in NX's absolute frame: mom_msys_origin, and mom_msys_matrix's first two
# rows, the MCS's X and Y axes (as NX writes them to the CLSF's MSYS record).
proc MOM_msys {} {
    set ns ::redpost_post
    ${ns}::next_event
    upvar #0 mom_msys_matrix m
    if {![array exists m] || ![array exists ::mom_msys_origin]} {
        ${ns}::abort MOM_msys "mom_msys_origin and mom_msys_matrix are not set"
    }
    ${ns}::send MOM_msys machine_frame [${ns}::vec mom_msys_origin] \
        [list $m(0) $m(1) $m(2)] [list $m(3) $m(4) $m(5)]
}

# A coordinate system other than the MCS (mom_csys_matrix: rotation 0..8, origin 9..11): the
# points after it would be in another frame, which redpost does not take (as a CL file's CSYS).
proc MOM_set_csys {} {
    set ns ::redpost_post
    ${ns}::next_event
    upvar #0 mom_csys_matrix m
    if {![array exists m]} {
        return
    }
    set identity {1 0 0 0 1 0 0 0 1 0 0 0}
    for {set k 0} {$k < 12} {incr k} {
        if {![info exists m($k)] || abs($m($k) - [lindex $identity $k]) > 1e-9} {
            ${ns}::abort MOM_set_csys "a coordinate system other than the MCS\
                (mom_csys_matrix not the identity) is not supported: the points after it would\
                be in another frame; output the operation in the MCS"
        }
    }
}

proc MOM_tool_change {} {
    ::redpost_post::next_event
    ::redpost_post::tool_change MOM_tool_change
}

# NX calls MOM_first_tool instead of MOM_tool_change for the first tool of the program.
proc MOM_first_tool {} {
    ::redpost_post::next_event
    ::redpost_post::tool_change MOM_first_tool
}

# LOAD/TOOL: the tool of MOM_tool_change again (nothing to do), or a tool change of its own.
proc MOM_load_tool {} {
    set ns ::redpost_post
    ${ns}::next_event
    if {[set ${ns}::tool_changed] ne [${ns}::mom mom_tool_number 0]} {
        ${ns}::tool_change MOM_load_tool
    }
}

# The next tool to fetch: nothing for the program (a robot's tool change is the cell's routine).
proc MOM_tool_preselect {} {
    ::redpost_post::next_event
}

proc MOM_spindle_rpm {} {
    set ns ::redpost_post
    ${ns}::next_event
    if {[string toupper [${ns}::mom mom_spindle_mode RPM]] eq "SFM"} {
        ${ns}::abort MOM_spindle_rpm "surface speed (mom_spindle_mode SFM) is not supported;\
            give the spindle speed in RPM"
    }
    set rpm [${ns}::mom mom_spindle_rpm [${ns}::mom mom_spindle_speed 0]]
    switch -- [string toupper [${ns}::mom mom_spindle_direction CLW]] {
        CLW - CW { set dir CW }
        CCLW - CCW { set dir CCW }
        default { set dir OFF }
    }
    ${ns}::send MOM_spindle_rpm spindle $rpm $dir
}

proc MOM_spindle_css {} {
    ::redpost_post::next_event
    ::redpost_post::abort MOM_spindle_css "constant surface speed is not supported; give the\
        spindle speed in RPM"
}

proc MOM_spindle_off {} {
    ::redpost_post::next_event
    ::redpost_post::send MOM_spindle_off spindle 0 OFF
}

proc MOM_coolant_on {} {
    ::redpost_post::next_event
    ::redpost_post::send MOM_coolant_on coolant 1 \
        [string toupper [::redpost_post::mom mom_coolant_mode ON]]
}

proc MOM_coolant_off {} {
    ::redpost_post::next_event
    ::redpost_post::send MOM_coolant_off coolant 0 OFF
}

# Cutter radius compensation: KRL has none; the session warns that the CL points are the tool's
# centre (NX's "centerline data").
proc MOM_cutcom_on {} {
    ::redpost_post::next_event
    ::redpost_post::send MOM_cutcom_on cutcom 1 \
        [string toupper [::redpost_post::mom mom_cutcom_mode ON]]
}

proc MOM_cutcom_off {} {
    ::redpost_post::next_event
    ::redpost_post::send MOM_cutcom_off cutcom 0 OFF
}

# A dwell: mom_delay_value seconds, or mom_delay_revs revolutions at mom_spindle_rpm.
proc MOM_delay {} {
    set ns ::redpost_post
    ${ns}::next_event
    if {[string match -nocase REV* [${ns}::mom mom_delay_mode SECONDS]]} {
        set rpm [${ns}::mom mom_spindle_rpm 0]
        if {!($rpm > 0)} {
            ${ns}::abort MOM_delay "a dwell in revolutions, but the spindle speed is not known"
        }
        set seconds [expr {60.0 * [${ns}::mom mom_delay_revs 0] / $rpm}]
    } else {
        set seconds [${ns}::mom mom_delay_value 0]
    }
    ${ns}::send MOM_delay dwell $seconds
}

# --- text -----------------------------------------------------------------------------------------

proc MOM_pprint {} {
    ::redpost_post::next_event
    ::redpost_post::send MOM_pprint operator_text pprint [::redpost_post::mom mom_pprint]
}

proc MOM_operator_message {} {
    ::redpost_post::next_event
    ::redpost_post::send MOM_operator_message operator_text message \
        [::redpost_post::mom mom_operator_message]
}

# The Insert UDE: operator text, written as a comment; only "KRL: statement" passes a KRL
# statement to the program (checked there), as INSERT/KRL: does in a CL file.
proc MOM_insert {} {
    ::redpost_post::next_event
    ::redpost_post::send MOM_insert operator_text insert \
        [string trim [::redpost_post::mom mom_Instruction]]
}

# --- motions --------------------------------------------------------------------------------------

# NX calls it before every motion event; the motion's own handler does the work.
proc MOM_before_motion {} {
}

proc MOM_initial_move {} {
    ::redpost_post::next_event
    ::redpost_post::first_motion MOM_initial_move
}

proc MOM_first_move {} {
    ::redpost_post::next_event
    ::redpost_post::first_motion MOM_first_move
}

proc MOM_from_move {} {
    ::redpost_post::next_event
    ::redpost_post::motion MOM_from_move [expr {[::redpost_post::mom mom_motion_type] eq "RAPID"}]
}

proc MOM_gohome_move {} {
    ::redpost_post::next_event
    ::redpost_post::motion MOM_gohome_move \
        [expr {[::redpost_post::mom mom_motion_type] eq "RAPID"}]
}

proc MOM_rapid_move {} {
    incr ::redpost_post::seq
    ::redpost_post::motion MOM_rapid_move 1
}

# The event of most of a toolpath, on the shortest path (the general one is motion).
proc MOM_linear_move {} {
    global mom_mcs_goto mom_tool_axis mom_feed_rate ::redpost_post::seq ::redpost_post::cycle_on \
        ::redpost_post::feed_sent ::redpost_post::session ::redpost_post::source_line \
        ::redpost_post::last_event ::redpost_post::line_sent ::redpost_post::replaying
    incr seq
    if {$cycle_on || $session eq "" || ![array exists mom_tool_axis]} {
        ::redpost_post::motion MOM_linear_move 0
        return
    }
    if {[info exists mom_feed_rate] && $mom_feed_rate ne $feed_sent} {
        ::redpost_post::feed_for MOM_linear_move
    }
    set line [expr {$replaying ? $source_line : $seq}]
    if {$last_event ne "MOM_linear_move"} {
        ::redpost_post::note_event $line MOM_linear_move
    }
    if {[catch {::redpost::linear_move $session $mom_mcs_goto(0) $mom_mcs_goto(1) \
                    $mom_mcs_goto(2) $mom_tool_axis(0) $mom_tool_axis(1) $mom_tool_axis(2) \
                    $line} message options]} {
        ::redpost_post::failed MOM_linear_move $message $options
    }
    set line_sent $line
}

proc MOM_circular_move {} {
    ::redpost_post::next_event
    ::redpost_post::circular MOM_circular_move
}

proc MOM_helix_move {} {
    ::redpost_post::next_event
    ::redpost_post::circular MOM_helix_move
}

proc MOM_nurbs_move {} {
    ::redpost_post::next_event
    ::redpost_post::nurbs MOM_nurbs_move
}

# --- drilling cycles ------------------------------------------------------------------------------

proc MOM_drill {} {
    ::redpost_post::next_event
    ::redpost_post::cycle MOM_drill 0
}

proc MOM_drill_dwell {} {
    ::redpost_post::next_event
    ::redpost_post::cycle MOM_drill_dwell 0
}

proc MOM_drill_deep {} {
    ::redpost_post::next_event
    ::redpost_post::cycle MOM_drill_deep 1
}

proc MOM_drill_break_chip {} {
    ::redpost_post::next_event
    ::redpost_post::cycle MOM_drill_break_chip 1
}

foreach ::redpost_post::e {drill_move drill_dwell_move drill_deep_move drill_break_chip_move} {
    proc MOM_$::redpost_post::e {} [format {
        ::redpost_post::next_event
        ::redpost_post::hole MOM_%s
    } $::redpost_post::e]
}

# The cycles redpost does not expand: refused, as their CYCLE/ records are in a CL file.
foreach ::redpost_post::e {tap bore bore_dwell bore_drag bore_no_drag bore_back bore_manual
    bore_manual_dwell drill_counter_sink drill_csink_dwell drill_text} {
    proc MOM_$::redpost_post::e {} [format {
        ::redpost_post::next_event
        ::redpost_post::abort MOM_%s "this cycle is not supported; redpost expands only\
            drilling cycles (MOM_drill, MOM_drill_dwell, MOM_drill_deep, MOM_drill_break_chip):\
            output this operation's holes with one of them, or as linear moves"
    } $::redpost_post::e]
}

proc MOM_cycle_off {} {
    ::redpost_post::next_event
    ::redpost_post::send MOM_cycle_off cycle_off
    set ::redpost_post::cycle_on 0
}

# The next hole's top is higher than the last's: every hole of redpost's expansion starts and
# ends at its own retract height, so nothing to do.
proc MOM_cycle_plane_change {} {
    ::redpost_post::next_event
}
