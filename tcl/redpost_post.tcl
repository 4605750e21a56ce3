# redpost_post.tcl: NX Post (MOM) event handlers that stream the toolpath into redpost and write
# a KUKA KRL program (.src/.dat) for a redundant robotic milling cell.
#
# Source this file from the event handler file of an NX postprocessor (docs/nx-integration.md).
# It reads its settings from redpost_settings.tcl next to it (or $env(REDPOST_SETTINGS)), loads
# the redpost Tcl package and defines the MOM_* procs below. Every event becomes one call of the
# C ABI session (redpost.h) through the ::redpost:: commands, so NX gives the same KRL, byte for
# byte, as `redpost convert` on the same toolpath.
#
# Variables read (NX's names, HANDLERS.md): mom_mcs_goto(0..2) and mom_tool_axis(0..2) for every
# motion (MCS, not machine coordinates: the robot's kinematics is redpost's job), mom_motion_type
# and mom_motion_event, mom_feed_rate (mm/min), mom_spindle_rpm / mom_spindle_speed,
# mom_spindle_direction (CLW/CCLW/NONE/OFF), mom_coolant_mode, mom_tool_name, mom_tool_number,
# mom_tool_diameter, mom_tool_length, mom_path_name / mom_operation_name, mom_arc_center /
# mom_pos_arc_center, mom_arc_axis, mom_arc_radius, mom_arc_direction, mom_pprint,
# mom_operator_message, mom_Instruction, mom_part_name, mom_output_file_full_name.
#
# Messages go to MOM_output_to_listing_device (NX's information window) when that command
# exists, to stdout otherwise. An error of the plugin (an unreachable pose, a joint limit, bad
# input) abandons the program (nothing is written) and aborts the postprocess: MOM_abort with
# the event and the reason in NX, a Tcl error elsewhere.

namespace eval ::redpost_post {
    variable here [file dirname [file normalize [info script]]]
    # The session handle of the program being written ("" : none).
    variable session ""
    # Set by hosts that replay a CL file (nx_replay.tcl): the CL line of the event being
    # handled, passed to the session before the event. "" in NX: the session counts events.
    variable source_line ""
    # The feed last given to the session (mm/min), so that it is sent when it changes.
    variable feed_sent ""
}

# Settings first: they say where the package is.
if {[info exists ::env(REDPOST_SETTINGS)] && $::env(REDPOST_SETTINGS) ne ""} {
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

namespace eval ::redpost_post {

    # A message for the user: NX's listing device, or stdout.
    proc tell {text} {
        if {[llength [info commands ::MOM_output_to_listing_device]]} {
            ::MOM_output_to_listing_device $text
        } else {
            puts stdout $text
        }
    }

    # Stops the postprocess after an error in the event $event: the session is abandoned (no
    # file is written) and the user sees the event and the reason.
    proc abort {event message {code {REDPOST ERROR}}} {
        variable session
        if {$session ne ""} {
            catch {::redpost::free $session}
            set session ""
        }
        set text "redpost: $event: $message"
        if {[llength [info commands ::MOM_abort]]} {
            tell $text
            ::MOM_abort $text
        }
        return -code error -errorcode $code $text
    }

    # One call of the session for the event $event: ::redpost::$command session args...
    proc send {event command args} {
        variable session
        variable source_line
        if {$session eq ""} {
            abort $event "no redpost program is open (MOM_start_of_program did not run or failed)"
        }
        if {[catch {
            if {$source_line ne ""} {
                ::redpost::set_line $session $source_line
            }
            ::redpost::$command $session {*}$args
        } message options]} {
            abort $event $message [dict get $options -errorcode]
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

    # A path from the settings: relative to the settings file's directory.
    proc setting_path {value} {
        if {$value eq ""} {
            return ""
        }
        return [file normalize [file join $::redpost_settings::dir $value]]
    }

    # A template set: a file, or the name of a shipped set (krc4_lin, krc4_spline, krc2_lin,
    # krc4_circ), which the library finds among its definitions.
    proc krl_path {value} {
        if {$value ne "" && [file extension $value] eq "" && [string first / $value] < 0} {
            return $value
        }
        return [setting_path $value]
    }

    # A KRL identifier from a file name, as `redpost convert` makes it: letters, digits and _,
    # a letter first, at most 19 characters (room for _P001).
    proc program_name_from {path} {
        set stem [file rootname [file tail $path]]
        regsub -all {[^A-Za-z0-9_]} $stem _ name
        if {$name eq "" || ![string is alpha [string index $name 0]]} {
            set name P$name
        }
        return [string range $name 0 18]
    }

    # The session options from the settings and NX's output file.
    proc open_options {} {
        namespace upvar ::redpost_settings \
            cell cell krl krl output_dir output_dir program_name program_name \
            placement placement base base tool tool apo apo split split \
            cl_line_every cl_line_every chordal_tol chordal_tol joints_csv joints_csv \
            source source tools tools clearance clearance rapid_vel rapid_vel max_bytes max_bytes
        if {[string toupper [mom mom_output_unit MM]] in {IN INCH}} {
            error "the post outputs inches (mom_output_unit IN): redpost takes mm; set the\
                postprocessor's output unit to metric"
        }
        set output_file [mom mom_output_file_full_name]
        set dir $output_dir
        if {$dir eq ""} {
            set dir [expr {$output_file ne "" ? [file dirname $output_file] : [pwd]}]
        }
        set name $program_name
        if {$name eq ""} {
            if {$output_file eq ""} {
                error "no program name: set program_name in redpost_settings.tcl"
            }
            set name [program_name_from $output_file]
        }
        set src $source
        if {$src eq ""} {
            set src [expr {[mom mom_part_name] ne "" ? [mom mom_part_name] : $output_file}]
        }
        set opts [list -cell [setting_path $cell] -output [setting_path $dir] -name $name \
                      -base $base -tool $tool -apo $apo -split $split \
                      -cl-line-every $cl_line_every -chordal-tol $chordal_tol \
                      -clearance $clearance -rapid-vel $rapid_vel -max-bytes $max_bytes]
        if {$tools ne ""} {
            lappend opts -tools [setting_path $tools]
        }
        if {$krl ne ""} {
            lappend opts -krl [krl_path $krl]
        }
        if {$joints_csv ne ""} {
            lappend opts -joints-csv [setting_path $joints_csv]
        }
        if {[llength $placement]} {
            lappend opts -placement $placement
        }
        if {$src ne ""} {
            lappend opts -source $src
        }
        return $opts
    }

    # A motion to mom_mcs_goto with mom_tool_axis: a rapid traverse or a feed move.
    proc motion {event rapid} {
        variable feed_sent
        if {$rapid} {
            send $event rapid
        } else {
            # NX has no feed event: mom_feed_rate holds the feed of each motion (on rapids, the
            # traverse rate, which is not sent).
            set feed [mom mom_feed_rate]
            if {[string is double -strict $feed] && $feed > 0 && $feed ne $feed_sent} {
                send $event feed $feed
                set feed_sent $feed
            }
        }
        send $event linear_move {*}[vec mom_mcs_goto] {*}[vec mom_tool_axis {0 0 1}]
    }

    # The first motion of a path (MOM_initial_move, MOM_first_move): a rapid or a feed move,
    # as mom_motion_event / mom_motion_type say.
    proc first_motion {event} {
        set rapid [expr {[mom mom_motion_event] eq "rapid_move" ||
                         ([mom mom_motion_event] ni {linear_move circular_move}
                          && [mom mom_motion_type] eq "RAPID")}]
        if {[mom mom_motion_event] eq "circular_move"} {
            ::MOM_circular_move
        } else {
            motion $event $rapid
        }
    }
}

# --- program ------------------------------------------------------------------------------------

proc MOM_start_of_program {} {
    set ns ::redpost_post
    if {[set ${ns}::session] ne ""} {
        catch {::redpost::free [set ${ns}::session]}
        set ${ns}::session ""
    }
    set ${ns}::feed_sent ""
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

# --- operations and tools -------------------------------------------------------------------------

proc MOM_start_of_path {} {
    set name [::redpost_post::mom mom_path_name [::redpost_post::mom mom_operation_name]]
    ::redpost_post::send MOM_start_of_path operation_start $name
}

proc MOM_end_of_path {} {
    ::redpost_post::send MOM_end_of_path operation_end
}

proc MOM_tool_change {} {
    set ns ::redpost_post
    ${ns}::send MOM_tool_change tool_change [${ns}::mom mom_tool_number 0] \
        [${ns}::mom mom_tool_name] [${ns}::mom mom_tool_diameter 0] [${ns}::mom mom_tool_length 0]
}

# NX calls MOM_first_tool instead of MOM_tool_change for the first tool of the program.
proc MOM_first_tool {} {
    MOM_tool_change
}

proc MOM_spindle_rpm {} {
    set ns ::redpost_post
    set rpm [${ns}::mom mom_spindle_rpm [${ns}::mom mom_spindle_speed 0]]
    switch -- [string toupper [${ns}::mom mom_spindle_direction CLW]] {
        CLW - CW { set dir CW }
        CCLW - CCW { set dir CCW }
        default { set dir OFF }
    }
    ${ns}::send MOM_spindle_rpm spindle $rpm $dir
}

proc MOM_spindle_off {} {
    ::redpost_post::send MOM_spindle_off spindle 0 OFF
}

proc MOM_coolant_on {} {
    ::redpost_post::send MOM_coolant_on coolant 1 [::redpost_post::mom mom_coolant_mode ON]
}

proc MOM_coolant_off {} {
    ::redpost_post::send MOM_coolant_off coolant 0 [::redpost_post::mom mom_coolant_mode OFF]
}

# --- text -----------------------------------------------------------------------------------------

proc MOM_pprint {} {
    ::redpost_post::send MOM_pprint comment [::redpost_post::mom mom_pprint]
}

proc MOM_operator_message {} {
    ::redpost_post::send MOM_operator_message comment [::redpost_post::mom mom_operator_message]
}

# The Insert UDE: operator text, written as a comment; only "KRL: statement" passes a KRL
# statement to the program (checked there), as INSERT/KRL: does in a CL file.
proc MOM_insert {} {
    set text [string trim [::redpost_post::mom mom_Instruction]]
    if {[string equal -nocase -length 4 $text "KRL:"]} {
        ::redpost_post::send MOM_insert literal [string trim [string range $text 4 end]]
    } else {
        ::redpost_post::tell "redpost: the Insert text '$text' is written as a comment, not as\
            KRL code (write 'KRL: statement' to pass a statement through)"
        ::redpost_post::send MOM_insert comment $text
    }
}

# --- motions --------------------------------------------------------------------------------------

proc MOM_initial_move {} {
    ::redpost_post::first_motion MOM_initial_move
}

proc MOM_first_move {} {
    ::redpost_post::first_motion MOM_first_move
}

proc MOM_rapid_move {} {
    ::redpost_post::motion MOM_rapid_move 1
}

proc MOM_linear_move {} {
    ::redpost_post::motion MOM_linear_move 0
}

# An arc (or a helix) about mom_arc_axis through the centre: mom_arc_center (MCS, like
# mom_mcs_goto) when NX provides it, mom_pos_arc_center otherwise. mom_arc_direction CLW means
# clockwise looking down the axis, i.e. negative about it by the right-hand rule that
# rp_circular_move follows, so the axis is reversed for it.
proc MOM_circular_move {} {
    set ns ::redpost_post
    set feed [${ns}::mom mom_feed_rate]
    if {[string is double -strict $feed] && $feed > 0 && $feed ne [set ${ns}::feed_sent]} {
        ${ns}::send MOM_circular_move feed $feed
        set ${ns}::feed_sent $feed
    }
    if {[array exists ::mom_arc_center]} {
        set centre [${ns}::vec mom_arc_center]
    } else {
        set centre [${ns}::vec mom_pos_arc_center]
    }
    set axis [${ns}::vec mom_arc_axis [${ns}::vec mom_tool_axis {0 0 1}]]
    if {[string toupper [${ns}::mom mom_arc_direction CCLW]] in {CLW CW}} {
        set axis [lmap c $axis {expr {-$c}}]
    }
    ${ns}::send MOM_circular_move circular_move {*}$centre {*}$axis \
        [${ns}::mom mom_arc_radius 0] {*}[${ns}::vec mom_mcs_goto] {*}[${ns}::vec mom_tool_axis {0 0 1}]
}

proc MOM_helix_move {} {
    MOM_circular_move
}

proc MOM_nurbs_move {} {
    ::redpost_post::abort MOM_nurbs_move "NURBS motions are not supported by the redpost handlers:\
        output them as linear moves (or circles) in the postprocessor's motion settings"
}
