# nx_replay_cl.tcl: the CL file read as NX's postprocessor would give its toolpath, record by
# record, as MOM events (nx_replay.tcl). APT/CLDATA and NX CLSF as docs/cl-format.md describes
# them: `$` continuations, `$$` comments, MULTAX, UNITS, the feed per revolution, the NX sign of
# CIRCLE's axis, NX's NURBS form, drilling cycles. Sourced by nx_replay.tcl.

namespace eval ::nx_replay {
    variable chan ""
    variable path ""
    variable lineno 0
    # The record: its first line, its major word (upper case) and what follows its '/'.
    variable rec_line 0
    variable word ""
    variable args ""
    # The warnings NX would not give (the file's own: unknown words, no UNITS), in convert's
    # words, given to the session at the end as the reader's are.
    variable warnings {}
    variable warned
    array set warned {}
    variable unknown_count 0
}

proc ::nx_replay::fail {message {line ""}} {
    variable path
    variable rec_line
    if {$line eq ""} {
        set line $rec_line
    }
    error "nx_replay: $path:$line: $message"
}

proc ::nx_replay::warn_once {key message {line ""}} {
    variable warned
    variable warnings
    variable path
    variable rec_line
    if {[info exists warned($key)]} {
        return
    }
    set warned($key) 1
    lappend warnings "$path:[expr {$line eq "" ? $rec_line : $line}]: $message"
}

# The record that starts with the physical line `line` (its number in lineno) into rec_line,
# word and args, its continuation lines read; 0 when it is blank (a comment-only line).
proc ::nx_replay::read_record {line} {
    variable chan
    variable lineno
    variable rec_line
    variable word
    variable args
    set rec ""
    set first 1
    while 1 {
        if {$first == 0} {
            if {[gets $chan line] < 0} {
                fail "the record ends with the continuation mark '\$' but the file ends here" \
                    $lineno
            }
            incr lineno
        }
        if {$lineno == 1 && [string index $line 0] eq "\ufeff"} {
            set line [string range $line 1 end]
        }
        set c [string first {$$} $line]
        if {$c >= 0} {
            set line [string range $line 0 $c-1]
        }
        set line [string trimright $line]
        set continued [expr {[string index $line end] eq "\$"}]
        if {$continued} {
            set line [string range $line 0 end-1]
        }
        if {$first} {
            set rec_line $lineno
            set first 0
        }
        append rec $line
        if {$continued} {
            continue
        }
        if {[string trim $rec] eq ""} {
            return 0
        }
        break
    }
    set rec [string trimleft $rec]
    set slash [string first / $rec]
    if {$slash >= 0} {
        set w [string range $rec 0 $slash-1]
        set args [string range $rec $slash+1 end]
    } else {
        set gap [string first " " $rec]
        set w $rec
        set args ""
        if {$gap > 0 && [string toupper [string range $rec 0 $gap-1]] in {PARTNO PPRINT INSERT}} {
            set w [string range $rec 0 $gap-1]
            set args [string range $rec $gap+1 end]
        }
    }
    set word [string toupper [regsub -all {\s+} [string trim $w] " "]]
    return 1
}

# The values after '/', trimmed; an empty one is refused.
proc ::nx_replay::fields {} {
    variable args
    variable word
    if {[string trim $args] eq ""} {
        return {}
    }
    set out {}
    foreach f [split $args ,] {
        set f [string trim $f]
        if {$f eq ""} {
            fail "empty value in $word/"
        }
        lappend out $f
    }
    return $out
}

# A number of the record (finite; Tcl reads it as the reader does, correctly rounded).
proc ::nx_replay::num {text} {
    if {![string is double -strict $text] || [string match -nocase *\[xni\]* $text]} {
        fail "not a number: '$text'"
    }
    return $text
}

namespace eval ::nx_replay {
    # The machine state of the file, as NX would hold it for the toolpath.
    variable started 0
    variable nx 0
    variable unit 1.0
    variable units_given 0
    variable multax 0
    variable axis {0 0 1}
    variable axis_known 0
    variable pos {0 0 0}
    variable pos_known 0
    variable rapid_next 0
    variable feed_known 0
    variable feed_per_rev 0
    variable feed_mm_per_rev 0.0
    variable spindle_rpm 0.0
    variable last_rpm 0.0
    variable last_direction CLW
    variable tool_count 0
    # The handler of the next motion: MOM_initial_move, MOM_first_move or "".
    variable first MOM_initial_move
    # CIRCLE waiting for its GOTO: {centre axis radius line}; NURBS being collected.
    variable arc {}
    variable nurbs_line 0
    variable nurbs_rapid 0
    variable knots {}
    variable points {}
    # The drilling cycle: on, and its definition (for CYCLE/ON) and retract height.
    variable cycle_on 0
    variable cycle_def {}
    variable cycle_retract 0.0
}

# A length of the file in mm.
proc ::nx_replay::mm {text} {
    variable unit
    set v [num $text]
    return [expr {$unit == 1.0 ? $v : $v * $unit}]
}

# A unit vector from three values, as the reader makes it: each divided by the length.
proc ::nx_replay::unit_vector {i j k} {
    set n [expr {sqrt($i * $i + $j * $j + $k * $k)}]
    if {!($n >= 1e-6)} {
        fail "the tool axis (i,j,k) has zero length"
    }
    return [list [expr {$i / $n}] [expr {$j / $n}] [expr {$k / $n}]]
}

proc ::nx_replay::start {} {
    variable started
    if {!$started} {
        set started 1
        set ::redpost_post::replaying 1
        set ::redpost_post::source_line $::nx_replay::rec_line
        MOM_start_of_program
    }
}

# One NX event: its line for the session, then the handler.
proc ::nx_replay::event {name} {
    variable rec_line
    start
    set ::redpost_post::source_line $rec_line
    $name
}

# The axis a motion without i,j,k takes.
proc ::nx_replay::current_axis {} {
    variable axis_known
    variable multax
    variable word
    variable axis
    if {!$axis_known && $multax} {
        fail "$word before any tool axis is known: with MULTAX/ON give TLAXIS/i,j,k or a GOTO\
            with i,j,k first"
    }
    return $axis
}

proc ::nx_replay::take_rapid {} {
    variable rapid_next
    set r $rapid_next
    set rapid_next 0
    return $r
}

proc ::nx_replay::units_warning {} {
    variable units_given
    if {!$units_given} {
        warn_once UNITS "no UNITS record before the first motion: coordinates are read as mm\
            (add UNITS/INCHES at the top of the file if the CAM system wrote inches)"
    }
}

# A motion event: mom_mcs_goto and mom_tool_axis set; `kind` is NX's motion event.
proc ::nx_replay::motion {kind rapid} {
    global mom_motion_event mom_motion_type
    variable first
    set mom_motion_event $kind
    set mom_motion_type [expr {$rapid ? "RAPID" : ($kind eq "drill_move" ? "CYCLE" : "CUT")}]
    event MOM_before_motion
    if {$first ne ""} {
        set f $first
        set first ""
        event $f
        return
    }
    switch -- $kind {
        rapid_move { event MOM_rapid_move }
        linear_move { event MOM_linear_move }
        circular_move { event MOM_circular_move }
        nurbs_move { event MOM_nurbs_move }
        drill_move { event $::nx_replay::hole_event }
    }
}

proc ::nx_replay::set_goto {p a} {
    global mom_mcs_goto mom_tool_axis
    lassign $p mom_mcs_goto(0) mom_mcs_goto(1) mom_mcs_goto(2)
    lassign $a mom_tool_axis(0) mom_tool_axis(1) mom_tool_axis(2)
}

# GOTO (a hole while a cycle is on, the end of a CIRCLE) and FROM.
proc ::nx_replay::on_goto {from} {
    variable axis
    variable axis_known
    variable arc
    variable cycle_on
    variable cycle_retract
    variable pos
    variable pos_known
    set f [fields]
    set n [llength $f]
    if {$n != 3 && $n != 6} {
        fail "GOTO takes 3 values (x,y,z) or 6 (x,y,z,i,j,k), got $n values"
    }
    lassign $f x y z i j k
    set p [list [mm $x] [mm $y] [mm $z]]
    if {$n == 6} {
        set axis [unit_vector [num $i] [num $j] [num $k]]
        set axis_known 1
    } else {
        current_axis
    }
    if {[llength $arc] && !$from} {
        end_arc $p
        return
    }
    units_warning
    set_goto $p $axis
    set rapid [take_rapid]
    if {$from} {
        set ::mom_motion_type [expr {$rapid ? "RAPID" : "FROM"}]
        set ::mom_motion_event from_move
        event MOM_before_motion
        event MOM_from_move
    } elseif {$cycle_on} {
        motion drill_move 0
    } else {
        motion [expr {$rapid ? "rapid_move" : "linear_move"}] $rapid
    }
    if {$cycle_on && !$from} {
        lassign $p px py pz
        lassign $axis ax ay az
        set pos [list [expr {$px + $cycle_retract * $ax}] [expr {$py + $cycle_retract * $ay}] \
                     [expr {$pz + $cycle_retract * $az}]]
    } else {
        set pos $p
    }
    set pos_known 1
}

# GODLTA: the point NX would give, from where the tool is.
proc ::nx_replay::on_godlta {} {
    variable pos
    variable pos_known
    set f [fields]
    if {[llength $f] != 1 && [llength $f] != 3} {
        fail "GODLTA takes 1 value (a distance along the tool axis) or 3 (dx,dy,dz)"
    }
    if {!$pos_known} {
        fail "GODLTA needs a known position, but no GOTO or FROM came before it"
    }
    set a [current_axis]
    lassign $pos px py pz
    if {[llength $f] == 1} {
        set d [mm [lindex $f 0]]
        lassign $a ax ay az
        set pos [list [expr {$px + $d * $ax}] [expr {$py + $d * $ay}] [expr {$pz + $d * $az}]]
    } else {
        lassign $f dx dy dz
        set pos [list [expr {$px + [mm $dx]}] [expr {$py + [mm $dy]}] [expr {$pz + [mm $dz]}]]
    }
    units_warning
    set_goto $pos $a
    set rapid [take_rapid]
    motion [expr {$rapid ? "rapid_move" : "linear_move"}] $rapid
}

# CIRCLE/xc,yc,zc,i,j,k[,r[,...]]: kept for the GOTO that ends it.
proc ::nx_replay::on_circle {} {
    variable arc
    variable nx
    variable pos_known
    variable rec_line
    set f [fields]
    set n [llength $f]
    if {$n != 6 && $n != 7 && $n != 11} {
        fail "CIRCLE takes 6 values (xc,yc,zc,i,j,k), 7 (...,r) or 11 (...,r,t,f,d,e), got $n"
    }
    if {!$pos_known} {
        fail "CIRCLE needs a start point, but no position is known yet"
    }
    current_axis
    lassign $f cx cy cz i j k r
    set arc [list [list [mm $cx] [mm $cy] [mm $cz]] [unit_vector [num $i] [num $j] [num $k]] \
                 [expr {$n >= 7 ? [mm $r] : ""}] $rec_line]
}

# NX gives an arc's centre, axis, direction and radius with its end: the CLSF's CIRCLE axis is
# written for clockwise travel (mom_arc_direction CLW), APT's for the right-hand rule (CCLW).
proc ::nx_replay::end_arc {end} {
    global mom_arc_center mom_arc_axis mom_arc_direction mom_arc_radius
    variable arc
    variable nx
    variable axis
    variable pos
    lassign $arc centre arc_axis radius
    set arc {}
    lassign $centre mom_arc_center(0) mom_arc_center(1) mom_arc_center(2)
    lassign $arc_axis mom_arc_axis(0) mom_arc_axis(1) mom_arc_axis(2)
    set mom_arc_direction [expr {$nx ? "CLW" : "CCLW"}]
    if {$radius eq ""} {
        unset -nocomplain mom_arc_radius
    } else {
        set mom_arc_radius $radius
    }
    set_goto $end $axis
    set rapid [take_rapid]
    motion circular_move $rapid
    set pos $end
}

# NURBS/ with its KNOT/ and CNTRL/ records: one MOM_nurbs_move once the block is complete.
proc ::nx_replay::on_nurbs {} {
    variable nurbs_line
    variable nurbs_rapid
    variable knots
    variable points
    variable pos_known
    variable rec_line
    if {!$pos_known} {
        fail "NURBS needs a start point, but no position is known yet"
    }
    current_axis
    set nurbs_line $rec_line
    set nurbs_rapid [take_rapid]
    set knots {}
    set points {}
}

proc ::nx_replay::end_nurbs {} {
    global mom_nurbs_knots mom_nurbs_points mom_nurbs_knot_count mom_nurbs_point_count
    variable nurbs_line
    variable nurbs_rapid
    variable knots
    variable points
    variable axis
    variable pos
    variable rec_line
    array unset mom_nurbs_knots
    array unset mom_nurbs_points
    set mom_nurbs_knot_count [llength $knots]
    set mom_nurbs_point_count [llength $points]
    set k 0
    foreach v $knots {
        set mom_nurbs_knots($k) $v
        incr k
    }
    set k 0
    foreach p $points {
        lassign $p mom_nurbs_points($k,0) mom_nurbs_points($k,1) mom_nurbs_points($k,2) \
            mom_nurbs_points($k,3)
        incr k
    }
    set ::mom_tool_axis(0) [lindex $axis 0]
    set ::mom_tool_axis(1) [lindex $axis 1]
    set ::mom_tool_axis(2) [lindex $axis 2]
    set line $rec_line
    set rec_line $nurbs_line
    motion nurbs_move $nurbs_rapid
    set rec_line $line
    if {[llength $points]} {
        set pos [lrange [lindex $points end] 0 2]
    }
    set knots {}
    set points {}
    set nurbs_line 0
}

proc ::nx_replay::on_knot {} {
    variable knots
    variable points
    if {[llength $points]} {
        fail "KNOT/ after CNTRL/: all knots must come before the control points"
    }
    foreach f [fields] {
        lappend knots [num $f]
    }
}

proc ::nx_replay::on_cntrl {} {
    variable points
    set f [fields]
    if {[llength $f] != 3 && [llength $f] != 4} {
        fail "CNTRL takes 3 values (x,y,z) or 4 (x,y,z,weight)"
    }
    lassign $f x y z w
    lappend points [list [mm $x] [mm $y] [mm $z] [expr {$w eq "" ? 1.0 : [num $w]}]]
}

source [file join $::here nx_replay_records.tcl]
