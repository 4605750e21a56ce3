# nx_replay_records.tcl: the CL records that set NX's state or give its other events (feed,
# spindle, coolant, tools, operations, MSYS, cycles, text), and the replay's loop
# (::nx_replay::run). Sourced by nx_replay_cl.tcl.

namespace eval ::nx_replay {
    variable hole_event MOM_drill_move
    variable fast 0
}

# A feed in mm/min from a value and its unit word, as NX gives mom_feed_rate.
proc ::nx_replay::feed_value {value unit} {
    variable spindle_rpm
    variable word
    switch -- [string toupper $unit] {
        MMPM { set v [num $value] }
        IPM { set v [expr {[num $value] * 25.4}] }
        MMPR - IPR {
            set per_rev [expr {[string toupper $unit] eq "IPR" ? [num $value] * 25.4 : [num $value]}]
            if {!($spindle_rpm > 0)} {
                fail "$word/..., $unit is a feed per revolution, but the spindle speed is not known"
            }
            set v [expr {$per_rev * $spindle_rpm}]
        }
        default { fail "unknown feed unit $unit" }
    }
    if {!($v > 0)} {
        fail "the feed must be > 0, got $value"
    }
    return $v
}

proc ::nx_replay::is_feed_unit {w} {
    return [expr {[string toupper $w] in {MMPM IPM MMPR IPR}}]
}

proc ::nx_replay::on_fedrat {} {
    variable unit
    variable feed_known
    variable feed_per_rev
    variable feed_mm_per_rev
    variable spindle_rpm
    set f [fields]
    set value [lindex $f 0]
    set u [expr {$unit == 1.0 ? "MMPM" : "IPM"}]
    if {[llength $f] == 2} {
        if {[is_feed_unit [lindex $f 0]]} {
            lassign $f u value
        } else {
            lassign $f value u
        }
    } elseif {[llength $f] != 1} {
        fail "FEDRAT takes f, f,MMPM or MMPM,f"
    }
    set v [feed_value $value $u]
    set feed_per_rev [expr {[string toupper $u] in {MMPR IPR}}]
    set feed_mm_per_rev [expr {$feed_per_rev ? $v / $spindle_rpm : 0.0}]
    set feed_known 1
    set ::mom_feed_rate $v
}

proc ::nx_replay::on_spindl {} {
    global mom_spindle_rpm mom_spindle_speed mom_spindle_direction mom_spindle_mode
    variable spindle_rpm
    variable last_rpm
    variable last_direction
    variable feed_known
    variable feed_per_rev
    variable feed_mm_per_rev
    set rpm ""
    set off 0
    set on 0
    set dir CLW
    set f [fields]
    for {set i 0} {$i < [llength $f]} {incr i} {
        set w [string toupper [lindex $f $i]]
        switch -- $w {
            RPM {}
            CLW - CCLW { set dir $w }
            OFF { set off 1 }
            ON { set on 1 }
            RANGE { incr i }
            SFM - SMM { fail "SPINDL: surface speed ($w) is not supported; give the speed in RPM" }
            default { set rpm [num [lindex $f $i]] }
        }
    }
    start
    if {$off || ($rpm ne "" && $rpm == 0)} {
        set spindle_rpm 0.0
        set mom_spindle_rpm 0
        set mom_spindle_direction NONE
        event MOM_spindle_off
        return
    }
    if {$rpm eq ""} {
        if {!$on || !($last_rpm > 0)} {
            fail "SPINDL/ needs a speed in RPM (SPINDL/n,RPM,CLW)"
        }
        set rpm $last_rpm
        set dir $last_direction
    }
    set spindle_rpm $rpm
    set last_rpm $rpm
    set last_direction $dir
    set mom_spindle_rpm $rpm
    set mom_spindle_speed $rpm
    set mom_spindle_mode RPM
    set mom_spindle_direction $dir
    event MOM_spindle_rpm
    if {$feed_known && $feed_per_rev} {
        set ::mom_feed_rate [expr {$feed_mm_per_rev * $rpm}]
    }
}

proc ::nx_replay::on_coolnt {} {
    set on 1
    set mode ""
    foreach w [fields] {
        set w [string toupper $w]
        switch -- $w {
            OFF { set on 0 }
            ON {}
            FLOOD - MIST - THRU - TAP { set mode $w }
            default { fail "COOLNT: unknown mode $w (use ON, OFF, FLOOD, MIST, THRU or TAP)" }
        }
    }
    start
    set ::mom_coolant_mode [expr {$mode ne "" ? $mode : ($on ? "ON" : "OFF")}]
    event [expr {$on ? "MOM_coolant_on" : "MOM_coolant_off"}]
}

# LOAD/TOOL,n and LOADTL/n (ADJUST, LENGTH couplets): NX's tool change of the tool the file's
# CUTTER, TLDATA and TOOL PATH describe; a tool change interrupts a cycle left on.
proc ::nx_replay::tool_change {f} {
    global mom_tool_number mom_tool_length
    variable tool_count
    variable first
    variable cycle_on
    lassign $f number
    set mom_tool_number [num $number]
    foreach {key value} [lrange $f 1 end] {
        if {[string toupper $key] eq "LENGTH"} {
            set mom_tool_length [mm $value]
        }
    }
    start
    set cycle_on 0
    event [expr {[incr tool_count] == 1 ? "MOM_first_tool" : "MOM_tool_change"}]
    event MOM_load_tool
    set first MOM_initial_move
}

proc ::nx_replay::on_cutter {} {
    set f [fields]
    set ::mom_tool_diameter [mm [lindex $f 0]]
    set ::mom_tool_length [expr {[llength $f] == 7 ? [mm [lindex $f 6]] : 0.0}]
}

proc ::nx_replay::on_tldata {} {
    set f [fields]
    if {[string toupper [lindex $f 0]] ne "MILL"} {
        warn_once "TLDATA [lindex $f 0]" "TLDATA/[lindex $f 0] not read: only TLDATA/MILL gives a\
            diameter and length redpost knows"
        set ::mom_tool_diameter 0.0
        set ::mom_tool_length 0.0
        return
    }
    set ::mom_tool_diameter [mm [lindex $f 1]]
    set ::mom_tool_length [mm [lindex $f 3]]
}

proc ::nx_replay::on_tool_path {} {
    variable first
    variable cycle_on
    set f [fields]
    set name [lindex $f 0]
    if {[llength $f] >= 3 && [string toupper [lindex $f 1]] eq "TOOL"} {
        set ::mom_tool_name [lindex $f 2]
    }
    start
    set cycle_on 0
    set ::mom_path_name $name
    set ::mom_operation_name $name
    event MOM_start_of_path
    if {$first ne "MOM_initial_move"} {
        set first MOM_first_move
    }
}

# MSYS/origin,X axis,Y axis: NX's MOM_msys (mom_msys_matrix rows: X, Y, Z of the MCS).
proc ::nx_replay::on_msys {} {
    global mom_msys_origin mom_msys_matrix
    set f [fields]
    if {[llength $f] != 9} {
        fail "MSYS takes 9 values (origin x,y,z, X axis i,j,k, Y axis i,j,k)"
    }
    lassign $f ox oy oz xi xj xk yi yj yk
    lassign [list [mm $ox] [mm $oy] [mm $oz]] mom_msys_origin(0) mom_msys_origin(1) \
        mom_msys_origin(2)
    set x [list [num $xi] [num $xj] [num $xk]]
    set y [list [num $yi] [num $yj] [num $yk]]
    set z [list [expr {$xj * $yk - $xk * $yj}] [expr {$xk * $yi - $xi * $yk}] \
               [expr {$xi * $yj - $xj * $yi}]]
    set k 0
    foreach v [concat $x $y $z] {
        set mom_msys_matrix($k) $v
        incr k
    }
    start
    event MOM_msys
}

# CSYS/12 values: NX's MOM_set_csys (mom_csys_matrix: rotation, then origin). Both layouts of
# the identity that CAM systems write are the MCS itself.
proc ::nx_replay::on_csys {} {
    global mom_csys_matrix
    set f [fields]
    if {[llength $f] != 12} {
        fail "CSYS takes 12 values (a 3 x 4 matrix)"
    }
    set v [lmap x $f {num $x}]
    set rows [expr {[lmap x $v {expr {double($x)}}] eq {1.0 0.0 0.0 0.0 0.0 1.0 0.0 0.0 0.0 0.0 1.0 0.0}}]
    if {$rows} {
        set v {1 0 0 0 1 0 0 0 1 0 0 0}
    }
    set k 0
    foreach x $v {
        set mom_csys_matrix($k) $x
        incr k
    }
    # No event of the session: the program starts with the first record that has one.
    set ::redpost_post::source_line $::nx_replay::rec_line
    MOM_set_csys
}

proc ::nx_replay::on_trntyp {} {
    set f [fields]
    if {[string toupper [lindex $f 0]] ne "WORLD" || [lsearch -not -exact [lmap x \
            [lrange $f 1 end] {expr {[num $x] == 0}}] 1] >= 0} {
        fail "TRNTYP/ other than TRNTYP/WORLD,0,0,0 is not supported"
    }
}

proc ::nx_replay::on_cutcom {} {
    set side [string toupper [lindex [fields] 0]]
    start
    if {$side in {LEFT RIGHT}} {
        set ::mom_cutcom_mode $side
        event MOM_cutcom_on
    } elseif {$side eq "OFF"} {
        event MOM_cutcom_off
    } else {
        fail "CUTCOM: expected LEFT, RIGHT or OFF, got $side"
    }
}

# CYCLE/DRILL[,DEEP|,BRKCHP], CYCLE/DEEP: NX's cycle event with its mom_cycle_* (the depth
# negative into the part, as NX gives mom_cycle_feed_to); CYCLE/OFF, CYCLE/ON.
proc ::nx_replay::on_cycle {} {
    variable cycle_on
    variable cycle_def
    variable cycle_retract
    variable feed_known
    variable hole_event
    set f [fields]
    set type [string toupper [lindex $f 0]]
    start
    switch -glob -- $type {
        OFF {
            set cycle_on 0
            event MOM_cycle_off
            return
        }
        INIT {
            return
        }
        ON {
            if {![llength $cycle_def]} {
                fail "CYCLE/ON without a cycle defined before it"
            }
            set f $cycle_def
        }
    }
    set type [string toupper [lindex $f 0]]
    set i 1
    set deep 0
    set breakchip 0
    if {$type eq "DRILL"} {
        set second [string toupper [lindex $f 1]]
        if {$second in {DEEP BRKCHP}} {
            set deep 1
            set breakchip [expr {$second eq "BRKCHP"}]
            set i 2
        }
    } elseif {[regexp {^DEEP[0-9]*$} $type]} {
        set deep 1
    } else {
        fail "CYCLE/$type is not supported; redpost expands only drilling cycles"
    }
    foreach var {mom_cycle_feed_to mom_cycle_rapid_to mom_cycle_retract_to mom_cycle_feed_rate
        mom_cycle_step1 mom_cycle_step2} {
        unset -nocomplain ::$var
    }
    set ::mom_cycle_delay 0
    set ::mom_cycle_delay_mode SECONDS
    foreach {key value} [lrange $f $i end] {
        switch -- [string toupper $key] {
            FEDTO { set ::mom_cycle_feed_to [expr {-[mm $value]}] }
            RAPTO { set ::mom_cycle_rapid_to [mm $value] }
            RTRCTO { set ::mom_cycle_retract_to [mm $value] }
            DWELL { set ::mom_cycle_delay [num $value] }
            1STPECK { set ::mom_cycle_step1 [mm $value] }
            SUBPECK { set ::mom_cycle_step2 [mm $value] }
            default {
                if {![is_feed_unit $key]} {
                    fail "CYCLE/$type: unknown parameter $key"
                }
                set ::mom_cycle_feed_rate [feed_value $value $key]
            }
        }
    }
    # NX always gives the cycle's feed: the feed in force when the cycle has none of its own.
    if {![info exists ::mom_cycle_feed_rate] && $feed_known} {
        set ::mom_cycle_feed_rate $::mom_feed_rate
    }
    set cycle_def $f
    set cycle_on 1
    set cycle_retract [expr {[info exists ::mom_cycle_retract_to] ? $::mom_cycle_retract_to
                             : [info exists ::mom_cycle_rapid_to] ? $::mom_cycle_rapid_to : 0.0}]
    set name [expr {$breakchip ? "MOM_drill_break_chip" : $deep ? "MOM_drill_deep"
                    : $::mom_cycle_delay > 0 ? "MOM_drill_dwell" : "MOM_drill"}]
    set hole_event ${name}_move
    event $name
}

# A major word NX has no event for and redpost does not know: warned of once, as convert does.
proc ::nx_replay::on_unknown {} {
    variable word
    variable warned
    variable unknown_count
    if {[info exists warned(word:$word)]} {
        return
    }
    if {[incr unknown_count] > 1000} {
        warn_once "many unknown words" "more than 1000 different unknown words; the others are\
            ignored without a warning"
        return
    }
    warn_once word:$word "unknown word $word ignored"
    start
}

# One record: the NX events it stands for.
proc ::nx_replay::record {} {
    variable word
    variable args
    variable nurbs_line
    variable arc
    variable started
    if {$nurbs_line != 0} {
        switch -- $word {
            KNOT { on_knot; return }
            CNTRL { on_cntrl; return }
            default { end_nurbs }
        }
    }
    if {[llength $arc] && $word ni {GOTO FEDRAT PAINT PPRINT INSERT SPINDL COOLNT CUTCOM}} {
        fail "CIRCLE at line [lindex $arc 3] must be followed by the GOTO that ends the arc,\
            not by $word"
    }
    switch -- $word {
        GOTO { on_goto 0 }
        FROM { on_goto 1 }
        GODLTA { on_godlta }
        RAPID { set ::nx_replay::rapid_next 1; start }
        CIRCLE { on_circle }
        NURBS { on_nurbs }
        KNOT - CNTRL { fail "$word/ outside a NURBS/ block" }
        CYCLE { on_cycle }
        FEDRAT { on_fedrat; start }
        SPINDL { on_spindl }
        COOLNT { on_coolnt }
        LOADTL { tool_change [fields] }
        LOAD {
            set f [fields]
            if {[string toupper [lindex $f 0]] ne "TOOL"} {
                fail "LOAD/ is supported only as LOAD/TOOL,n"
            }
            tool_change [lrange $f 1 end]
        }
        SELECT { start; event MOM_tool_preselect }
        CUTTER { on_cutter }
        TLDATA { on_tldata }
        {TOOL PATH} { on_tool_path }
        END-OF-PATH { start; event MOM_end_of_path }
        PARTNO {
            set name [string trim $args]
            if {!$started} {
                set ::mom_part_name $name
                start
            } else {
                set ::mom_operator_message "part $name"
                event MOM_operator_message
            }
        }
        PPRINT { start; set ::mom_pprint [string trim $args]; event MOM_pprint }
        INSERT { start; set ::mom_Instruction [string trim $args]; event MOM_insert }
        UNITS - UNIT {
            set u [string toupper [lindex [fields] 0]]
            set ::nx_replay::units_given 1
            set ::nx_replay::unit [expr {$u eq "MM" ? 1.0 : $u in {INCHES INCH} ? 25.4 :
                                         [fail "UNITS: unknown unit $u"]}]
        }
        MULTAX { set ::nx_replay::multax [expr {[string toupper [lindex [fields] 0]] ne "OFF"}] }
        TLAXIS {
            lassign [fields] i j k
            set ::nx_replay::axis [unit_vector [num $i] [num $j] [num $k]]
            set ::nx_replay::axis_known 1
        }
        MSYS { on_msys }
        CSYS { on_csys }
        TRNTYP { on_trntyp }
        CUTCOM { on_cutcom }
        PAINT {}
        END - FINI { start }
        ORIGIN - TRANS - ROTABL - COPY - INDEX { fail "$word is not supported" }
        default { on_unknown }
    }
}

# Whether the next plain GOTO may take fast_goto: no curve, cycle or first motion pending, mm.
proc ::nx_replay::set_fast {} {
    variable fast
    variable nurbs_line
    variable arc
    variable cycle_on
    variable first
    variable unit
    variable units_given
    variable rapid_next
    set fast [expr {!$nurbs_line && ![llength $arc] && !$cycle_on && $first eq "" && !$rapid_next &&
                    $unit == 1.0 && $units_given}]
}

# The common case of a toolpath, a plain GOTO in mm outside any curve, cycle or first motion, on
# the shortest path; false (nothing done) for every other line.
proc ::nx_replay::fast_goto {line} {
    variable axis
    variable pos
    variable lineno
    variable rec_line
    variable fast
    global mom_mcs_goto mom_tool_axis mom_motion_type mom_motion_event
    if {![string equal -length 5 $line GOTO/] || !$fast || [string first \$ $line] >= 0} {
        return 0
    }
    set v [split [string range $line 5 end] ,]
    set n [llength $v]
    if {$n == 6} {
        lassign $v x y z i j k
        if {![string is double -strict $i] || ![string is double -strict $j] ||
                ![string is double -strict $k]} {
            return 0
        }
        set norm [expr {sqrt($i * $i + $j * $j + $k * $k)}]
        if {!($norm >= 1e-6)} {
            return 0
        }
        set axis [list [set mom_tool_axis(0) [expr {$i / $norm}]] \
                      [set mom_tool_axis(1) [expr {$j / $norm}]] \
                      [set mom_tool_axis(2) [expr {$k / $norm}]]]
    } elseif {$n == 3} {
        lassign $v x y z
        lassign $axis mom_tool_axis(0) mom_tool_axis(1) mom_tool_axis(2)
    } else {
        return 0
    }
    if {![string is double -strict $x] || ![string is double -strict $y] ||
            ![string is double -strict $z] || [string first x $line] >= 0 ||
            [string first X $line] >= 0} {
        # Not a plain number (hex is not a CL number); NaN and Inf reach the session, which
        # refuses them at the line.
        return 0
    }
    set rec_line $lineno
    set pos [list [set mom_mcs_goto(0) $x] [set mom_mcs_goto(1) $y] [set mom_mcs_goto(2) $z]]
    set mom_motion_event linear_move
    set mom_motion_type CUT
    set ::redpost_post::source_line $lineno
    MOM_before_motion
    MOM_linear_move
    return 1
}

proc ::nx_replay::run {input} {
    variable chan
    variable path
    variable nx
    variable warnings
    variable word
    set path $input
    if {[catch {open $input r} chan]} {
        error "nx_replay: $input: $chan"
    }
    fconfigure $chan -encoding utf-8 -translation auto -buffersize 65536
    try {
        while {[gets $chan line] >= 0} {
            incr ::nx_replay::lineno
            if {[fast_goto $line]} {
                continue
            }
            if {![read_record $line]} {
                continue
            }
            if {!$nx && $word in {{TOOL PATH} TLDATA MSYS END-OF-PATH PAINT}} {
                set nx 1
            }
            record
            set_fast
        }
        if {$::nx_replay::nurbs_line != 0} {
            end_nurbs
        }
        if {[llength $::nx_replay::arc]} {
            fail "the file ends after CIRCLE without the GOTO that ends the arc"
        }
        start
        # The end of the program at the file's last line.
        set ::redpost_post::source_line $::nx_replay::lineno
        foreach w $warnings {
            ::redpost_post::warn $w
        }
        MOM_end_of_program
    } finally {
        close $chan
    }
}
