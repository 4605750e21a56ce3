# Tests of the redpost Tcl package (plugin/src/tcl_package.cpp), the NX event handlers
# (tcl/redpost_post.tcl) and the replay driver (tcl/nx_replay.tcl).
#
#   tclsh test_package.tcl LIBDIR SOURCE_DIR REDPOST WORK_DIR
#
# LIBDIR: the directory of pkgIndex.tcl and libredpost.so.N (build/plugin); REDPOST: the
# `redpost` command-line host, whose `convert` output the replay must equal byte for byte.
# Prints one line per failure and "N passed, M failed"; exits 1 on any failure.

if {$argc != 4} {
    puts stderr "usage: tclsh test_package.tcl LIBDIR SOURCE_DIR REDPOST WORK_DIR"
    exit 1
}
lassign $argv libdir src redpost work
set libdir [file normalize $libdir]
set src [file normalize $src]
set work [file normalize $work]
file delete -force $work
file mkdir $work

set passed 0
set failed 0

# check NAME SCRIPT ?EXPECTED?: SCRIPT's result must equal EXPECTED (default 1).
proc check {name script {expected 1}} {
    if {[catch {uplevel 1 $script} result options]} {
        puts "FAIL $name: error: $result"
        incr ::failed
        return
    }
    if {$result ne $expected} {
        puts "FAIL $name: got \"$result\", expected \"$expected\""
        incr ::failed
        return
    }
    incr ::passed
}

# check_error NAME SCRIPT CODE PATTERN: SCRIPT must fail with errorCode CODE (glob) and a
# message matching PATTERN (glob).
proc check_error {name script code pattern} {
    if {![catch {uplevel 1 $script} result options]} {
        puts "FAIL $name: no error (result \"$result\")"
        incr ::failed
        return
    }
    # A session's errorCode ends with the line it names: {REDPOST RP_ERR_... LINE}.
    set ec [lrange [dict get $options -errorcode] 0 1]
    if {![string match $code $ec] || ![string match $pattern $result]} {
        puts "FAIL $name: error \"$result\" (errorCode $ec), expected \"$pattern\" ($code)"
        incr ::failed
        return
    }
    incr ::passed
}

proc slurp {path} {
    set f [open $path rb]
    set data [read $f]
    close $f
    return $data
}

# Every file of dir a equals the file of the same name in dir b, and the names are the same.
proc same_dirs {a b} {
    set fa [lsort [lmap f [glob -nocomplain -directory $a *] {file tail $f}]]
    set fb [lsort [lmap f [glob -nocomplain -directory $b *] {file tail $f}]]
    if {$fa ne $fb} {
        return "files differ: {$fa} vs {$fb}"
    }
    if {![llength $fa]} {
        return "no files"
    }
    foreach f $fa {
        if {[slurp [file join $a $f]] ne [slurp [file join $b $f]]} {
            return "$f differs"
        }
    }
    return same
}

set cell $src/definitions/cells/andres2011_kr15_track_table.xml
set krl $src/definitions/krl
set cl $src/examples/cl

# --- the package ----------------------------------------------------------------------------------

set auto_path [linsert $auto_path 0 $libdir]
check package.require {package require redpost} 0.8.0
check package.version {::redpost::version} 0.8.0
check package.namespace {
    expr {[llength [info commands ::redpost::*]] >= 22}
}

# The package from an install layout: <libdir>/redpost0.8.0/pkgIndex.tcl, library one level up.
check package.install_layout {
    set inst $::work/install/lib
    file mkdir $inst/redpost0.8.0
    file copy [file join $::libdir pkgIndex.tcl] $inst/redpost0.8.0/
    # The real file under the SONAME (in the build tree libredpost.so.0 is a symlink).
    file copy [file join $::libdir libredpost.so.0.8.0] $inst/libredpost.so.0
    set child [interp create]
    $child eval [list set auto_path [linsert [$child eval set auto_path] 0 $inst]]
    set v [$child eval {package require redpost; ::redpost::version}]
    set loaded [$child eval {info loaded}]
    interp delete $child
    expr {$v eq "0.8.0" && [string match *install/lib/libredpost.so.0* $loaded]}
}

# --- usage errors ---------------------------------------------------------------------------------

check_error usage.open_required {::redpost::open -cell $cell} {REDPOST USAGE} *-cell*-output*-name*
check_error usage.open_option {::redpost::open -bogus 1} * {bad option "-bogus"*}
check_error usage.open_odd {::redpost::open -cell} * {wrong # args*}
check_error usage.no_session {::redpost::rapid rp999} {REDPOST NO_SESSION} {no redpost session "rp999"}
check_error usage.count {::redpost::feed} * {wrong # args: should be "::redpost::feed session mm_per_min"}
check_error usage.placement {
    ::redpost::open -cell $cell -output $work -name X -placement {1 2 3}
} {REDPOST USAGE} {-placement takes six numbers*}
check_error usage.deflection {
    ::redpost::open -cell $cell -output $work -name X -deflection sometimes
} * {bad -deflection "sometimes": must be off, predict, or compensate}
check_error error.cutting_without_model {
    ::redpost::open -cell $cell -output $work -name X -cutting $work/cut.xml
} {REDPOST RP_ERR_BAD_INPUT} {*no deflection prediction was asked*}
check_error error.fit_tol {
    ::redpost::open -cell $cell -output $work -name X -fit-tol -1
} {REDPOST RP_ERR_BAD_INPUT} {*--fit-tol is -1 mm: it must be 0 (no point reduction) or 0.001 to 1 mm*}
check_error error.fit_ang_tol {
    ::redpost::open -cell $cell -output $work -name X -fit-ang-tol 9
} {REDPOST RP_ERR_BAD_INPUT} {*--fit-ang-tol is 9 deg*}
check_error error.threads {
    ::redpost::open -cell $cell -output $work -name X -threads -1
} {REDPOST RP_ERR_BAD_INPUT} {*options.plan_threads is -1*}
check_error usage.fit_tol_number {
    ::redpost::open -cell $cell -output $work -name X -fit-tol fine
} {REDPOST USAGE} {expected a number for -fit-tol but got "fine"}
check_error usage.reader_count {::redpost::reader_open} * {wrong # args*}
check_error usage.no_reader {::redpost::reader_next rpreader99} {REDPOST NO_READER} *rpreader99*

# --- the deflection (issue 20): -deflection compensate moves the cutting target ------------------

file mkdir $work/deflection
check deflection.compensate {
    set ends {}
    foreach mode {predict compensate} {
        set d [::redpost::open -cell $cell -output $work/deflection -name D_$mode -plan local \
            -deflection $mode -deflection-tol 0.02]
        ::redpost::tool_change $d 1 MILL 16 0
        ::redpost::spindle $d 8000 CW
        ::redpost::feed $d 2000
        ::redpost::linear_move $d -100 -300 60 0 0 1
        ::redpost::linear_move $d -100 -320 60 0 0 1
        lappend ends [lrange [dict get [::redpost::last_move $d] joints] 0 8]
        ::redpost::close $d
        ::redpost::free $d
    }
    # The compensated posture differs from the predicted one (the target moved by tenths of mm).
    expr {[lindex $ends 0] ne [lindex $ends 1]}
}

# --- errors of the plugin ---------------------------------------------------------------------------

check_error error.missing_cell {
    ::redpost::open -cell $work/no_such_cell.xml -output $work -name X
} {REDPOST RP_ERR_*} *no_such_cell.xml*
check_error error.missing_cl {::redpost::reader_open $work/no_such.apt} {REDPOST RP_ERR_*} *no_such.apt*

file mkdir $work/session
# -plan local: every command is tracked when it is made, which last_move checks; the default
# global plan buffers the commands (see plan.global below).
set s [::redpost::open -cell $cell -output $work/session -name SESSION -source test.apt \
    -plan local]
check usage.not_a_number [list catch [list ::redpost::feed $s abc] m] 1
check usage.not_a_number_message {set m} {expected a number for mm_per_min but got "abc"}
check_error usage.spindle_direction {::redpost::spindle $s 1000 LEFT} * {bad direction "LEFT"*}

# --- a whole session, command by command ----------------------------------------------------------

check session.handle {string match rp* $s}
check session.events {
    ::redpost::set_line $s 1
    ::redpost::comment $s "made by test_package.tcl"
    ::redpost::operation_start $s POCKET
    ::redpost::tool_change $s 1 END_MILL_D10 10 75
    ::redpost::spindle $s 12000 CW
    ::redpost::coolant $s on FLOOD
    ::redpost::set_line $s 9
    ::redpost::rapid $s
    ::redpost::linear_move $s -120 -440 110 0 0 1
    ::redpost::feed $s 900
    ::redpost::set_line $s 11
    ::redpost::linear_move $s -120 -440 57 0 0 1
    ::redpost::linear_move $s -72 -480 57 0 0 1
    ::redpost::set_line $s 15
    ::redpost::circular_move $s -72 -468 57 0 0 1 12 -60 -468 57 0 0 1
    ::redpost::literal $s {$OUT[17] = TRUE ; a literal line}
    ::redpost::coolant $s 0 FLOOD
    ::redpost::spindle $s 0 OFF
    ::redpost::operation_end $s
} {}
check session.last_move {
    set m [::redpost::last_move $s]
    expr {[dict get $m joint_count] > 6 && [llength [dict get $m joints]] == [dict get $m joint_count]
          && [llength [dict get $m axes]] == 12 && [dict get $m inv_condition] > 0
          && [dict get $m position_error_mm] < 0.01}
}
check session.close {::redpost::close $s} {}
check session.summary {
    set sum [::redpost::summary $s]
    expr {[dict get $sum poses] >= 4 && [dict get $sum motions] >= 4
          && [dict get $sum files] eq [list $work/session/SESSION.src]}
}
check session.warnings {string is list [::redpost::warnings $s]}
check session.files {
    set text [slurp $work/session/SESSION.src]
    expr {[file exists $work/session/SESSION.dat] && [string match *DEF\ SESSION* $text]}
}
check session.literal {string match {*$OUT\[17\] = TRUE ; a literal line*} \
    [slurp $work/session/SESSION.src]} 1
# Free text is never KRL: a literal that is not one of the statements redpost checks is refused.
file mkdir $work/literal
set s_lit [::redpost::open -cell $cell -output $work/literal -name LIT -source lit.apt]
# A NUL in a Tcl string is the bytes C0 80 inside the package: refused before the ABI.
check_error session.nul_in_comment {::redpost::comment $s_lit "a\0b"} {REDPOST USAGE} \
    {the comment holds a NUL character*}
check_error session.nul_in_literal {::redpost::literal $s_lit "\$OUT\[1\] = TRUE\0"} \
    {REDPOST USAGE} {the literal holds a NUL character*}
check_error session.nul_in_tool_name {::redpost::tool_change $s_lit 1 "MILL\0X" 10 75} \
    {REDPOST USAGE} {the tool name holds a NUL character*}
check_error session.literal_refused {::redpost::literal $s_lit "this is not KRL at all !!"} \
    {REDPOST RP_ERR_BAD_INPUT} {*cannot be passed to the KRL program*}
::redpost::free $s_lit
check session.comment {string match "*made by test_package.tcl*" [slurp $work/session/SESSION.src]}
check_error session.after_close {::redpost::rapid $s} {REDPOST RP_ERR_STATE} *
check session.free {::redpost::free $s; info commands ::redpost::free} ::redpost::free
check_error session.freed {::redpost::close $s} {REDPOST NO_SESSION} *

# NaN coordinates: refused by the plugin, with the line.
file mkdir $work/nan
set s [::redpost::open -cell $cell -output $work/nan -name NAN -source nan.apt]
::redpost::rapid $s
::redpost::linear_move $s -120 -440 110 0 0 1
::redpost::set_line $s 42
check_error error.nan {::redpost::linear_move $s -120 NaN 110 0 0 1} {REDPOST RP_ERR_BAD_INPUT} *42*
check_error error.failed_session {::redpost::linear_move $s -120 -440 100 0 0 1} {REDPOST RP_ERR_STATE} *
catch {::redpost::close $s}
check error.nan_no_output {glob -nocomplain -directory $work/nan *} {}
::redpost::free $s

# An unreachable pose: the message names the line; nothing is written. Pose by pose the command
# that brings it fails; with the global plan the command that completes a window
# (plan.unreachable below).
file mkdir $work/far
set s [::redpost::open -cell $cell -output $work/far -name FAR -source far.apt -plan local]
::redpost::rapid $s
::redpost::linear_move $s -120 -440 110 0 0 1
::redpost::feed $s 1000
::redpost::set_line $s 77
check_error error.unreachable {::redpost::linear_move $s 5000 5000 110 0 0 1} \
    {REDPOST RP_ERR_*} *far.apt:77*
catch {::redpost::close $s}
check error.unreachable_no_output {glob -nocomplain -directory $work/far *} {}
::redpost::free $s

file mkdir $work/far_plan
set s [::redpost::open -cell $cell -output $work/far_plan -name FAR -source far.apt]
::redpost::rapid $s
::redpost::linear_move $s -120 -440 110 0 0 1
::redpost::feed $s 1000
::redpost::set_line $s 77
# The move is longer than the plan's horizon: the call that brings it is planned, and fails.
check_error plan.unreachable {::redpost::linear_move $s 5000 5000 110 0 0 1} \
    {REDPOST RP_ERR_*} {*far.apt:77: pose*}
catch {::redpost::close $s}
check plan.unreachable_no_output {glob -nocomplain -directory $work/far_plan *} {}
::redpost::free $s
check_error plan.bad_option {::redpost::open -cell $cell -output $work -name X -plan sideways} \
    * {bad -plan "sideways"*}

# -lock: E1 held at 700 mm in every written motion (as `redpost convert --lock E1=700`).
file mkdir $work/lock
check plan.lock {
    set s [::redpost::open -cell $cell -output $work/lock -name LOCK -source lock.apt \
        -lock {E1=700 E2}]
    ::redpost::rapid $s
    ::redpost::linear_move $s -120 -440 110 0 0 1
    ::redpost::feed $s 1000
    ::redpost::linear_move $s -120 -440 57 0 0 1
    ::redpost::linear_move $s -320 -640 57 0 0 1
    ::redpost::close $s
    ::redpost::free $s
    set e1 {}
    foreach {- v} [regexp -all -inline {E1 (-?[0-9.]+)} [slurp $work/lock/LOCK.src]] {
        lappend e1 [format %.1f $v]
    }
    list [llength $e1] [lsort -unique $e1]
} {3 700.0}
check_error plan.lock_bad_axis {::redpost::open -cell $cell -output $work -name X -lock {A1=5}} \
    {REDPOST USAGE} {-lock "A1=5": name an external axis E1..E6*}
check_error plan.lock_bad_value {::redpost::open -cell $cell -output $work -name X -lock {E1=far}} \
    {REDPOST USAGE} {expected a number for -lock but got "far"}
check_error plan.lock_infinite {::redpost::open -cell $cell -output $work -name X -lock {E1=inf}} \
    {REDPOST USAGE} {-lock "E1=inf": the value is not a finite number*}

# --- the reader ------------------------------------------------------------------------------------

check reader.events {
    set r [::redpost::reader_open $cl/pocket_arcs.apt 0.01]
    set kinds {}
    set moves 0
    set first ""
    while {[set e [::redpost::reader_next $r]] ne ""} {
        if {$first eq ""} {
            set first $e
        }
        dict incr kinds [dict get $e kind]
        if {[dict get $e kind] eq "move"} {
            incr moves
        }
    }
    set end [::redpost::reader_next $r]
    ::redpost::reader_free $r
    list [dict get $first kind] [dict get $first text] [dict get $first line] \
        [expr {$moves > 40}] [dict exists $kinds spindle] [dict exists $kinds coolant] $end
} {part_name {POCKET WITH ARCS} 1 1 1 1 {}}
check reader.free {
    set r [::redpost::reader_open $cl/long_pass.apt]
    ::redpost::reader_free $r
    catch {::redpost::reader_next $r}
} 1
check_error reader.syntax {
    set f [open $work/bad.apt w]
    puts $f "GOTO/1,2,3,4"
    close $f
    set r [::redpost::reader_open $work/bad.apt]
    try {::redpost::reader_next $r} finally {::redpost::reader_free $r}
} {REDPOST RP_ERR_BAD_INPUT} *bad.apt:1*

# --- interpreters ---------------------------------------------------------------------------------

# Sessions left open are freed with their interpreter (nothing written, no crash).
check interp.delete {
    file mkdir $work/child
    set child [interp create]
    $child eval [list set auto_path $auto_path]
    $child eval [list package require redpost]
    $child eval [list set s [list ::redpost::open -cell $cell -output $work/child -name CHILD]]
    $child eval {set s [{*}$s]; ::redpost::rapid $s; ::redpost::linear_move $s -120 -440 110 0 0 1}
    interp delete $child
    glob -nocomplain -directory $work/child *
} {}
# A safe interpreter gets the version only.
check interp.safe {
    set safe [interp create -safe]
    load [file join $libdir libredpost.so.0] Redpost $safe
    set r [list [$safe eval ::redpost::version] [llength [$safe eval {info commands ::redpost::*}]]]
    interp delete $safe
    set r
} {0.8.0 1}

# --- the handlers, as NX calls them -------------------------------------------------------------------

# A child interpreter as NX's: mom_* variables, MOM_abort and the listing device stubbed.
proc nx_interp {out settings} {
    set nx [interp create]
    $nx eval [list set auto_path $::auto_path]
    $nx eval {
        set ::listing {}
        set ::aborted {}
        proc MOM_output_to_listing_device {text} { lappend ::listing $text }
        proc MOM_abort {text} { lappend ::aborted $text }
    }
    set f [open $out/settings.tcl w]
    puts $f "source [list $::src/tcl/redpost_settings.tcl]"
    puts $f "namespace eval ::redpost_settings {$settings}"
    close $f
    set ::env(REDPOST_SETTINGS) $out/settings.tcl
    $nx eval [list source $::src/tcl/redpost_post.tcl]
    unset ::env(REDPOST_SETTINGS)
    return $nx
}

file mkdir $work/nx
set nx [nx_interp $work/nx "variable cell [list $cell]; variable krl krc4_lin"]
check handlers.program {
    $nx eval {
        set mom_output_file_full_name /nonexistent/pocket-1.ptp
    }
    $nx eval [list set redpost_settings::output_dir $work/nx]
    $nx eval {
        set mom_part_name /parts/pocket.prt
        MOM_start_of_program
        set mom_path_name ROUGH
        MOM_start_of_path
        set mom_tool_number 1; set mom_tool_name EM10; set mom_tool_diameter 10; set mom_tool_length 75
        MOM_first_tool
        set mom_spindle_rpm 12000; set mom_spindle_direction CLW
        MOM_spindle_rpm
        set mom_coolant_mode FLOOD
        MOM_coolant_on
        array set mom_tool_axis {0 0 1 0 2 1}
        array set mom_mcs_goto {0 -120 1 -440 2 110}
        set mom_motion_type RAPID; set mom_motion_event rapid_move; set mom_feed_rate 10000
        MOM_initial_move
        array set mom_mcs_goto {0 -120 1 -440 2 57}
        set mom_motion_type CUT; set mom_motion_event linear_move; set mom_feed_rate 900
        MOM_linear_move
        array set mom_mcs_goto {0 -72 1 -480 2 57}
        MOM_linear_move
        # A quarter circle counter-clockwise about +Z, then back clockwise.
        array set mom_arc_center {0 -72 1 -468 2 57}
        array set mom_arc_axis {0 0 1 0 2 1}
        set mom_arc_radius 12; set mom_arc_direction CCLW
        array set mom_mcs_goto {0 -60 1 -468 2 57}
        set mom_motion_event circular_move
        MOM_circular_move
        set mom_arc_direction CLW
        array set mom_mcs_goto {0 -72 1 -480 2 57}
        MOM_circular_move
        set mom_pprint "finishing"
        MOM_pprint
        MOM_coolant_off
        MOM_spindle_off
        MOM_end_of_path
        MOM_end_of_program
        list $::aborted [file exists $redpost_settings::output_dir/pocket_1.src]
    }
} {{} 1}
check handlers.listing {
    string match "*wrote*pocket_1.src*" [$nx eval {set ::listing}]
}
check handlers.arc_clockwise {
    # Both arcs were tracked as many short LINs, not as one chord.
    set text [slurp $work/nx/pocket_1.src]
    expr {[regexp -all {\nLIN } $text] > 10 && [string match *ROUGH* $text]
          && [string match *finishing* $text] && [string match "*part /parts/pocket.prt*" $text]}
}
interp delete $nx

# An unreachable pose in NX: MOM_abort with the event and the reason; nothing written.
file mkdir $work/nx_far
set nx [nx_interp $work/nx_far "variable cell [list $cell]; variable program_name FAR; variable output_dir [list $work/nx_far]"]
check handlers.abort {
    $nx eval {
        MOM_start_of_program
        array set mom_tool_axis {0 0 1 0 2 1}
        array set mom_mcs_goto {0 -120 1 -440 2 110}
        set mom_motion_type RAPID; set mom_motion_event rapid_move
        MOM_initial_move
        array set mom_mcs_goto {0 5000 1 5000 2 110}
        set mom_feed_rate 1000
        # The session tracks on its own thread (and plans ahead): the pose is found unreachable
        # by a later event at the latest, the end of the program, which names the event.
        set failed [catch {MOM_linear_move; MOM_end_of_program} message]
        list $failed [llength $::aborted] \
            [string match "redpost: MOM_linear_move (reported at *) (event 3 of the run):\
                *:3: pose * would have to leave its limits*" [lindex $::aborted 0]] \
            [expr {$message eq [lindex $::aborted 0]}]
    }
} {1 1 1 1}
check handlers.abort_no_output {glob -nocomplain -directory $work/nx_far *.src *.dat} {}
interp delete $nx

# A missing cell: the abort comes at MOM_start_of_program.
file mkdir $work/nx_nocell
set nx [nx_interp $work/nx_nocell "variable cell [list $work/none.xml]; variable program_name X; variable output_dir [list $work/nx_nocell]"]
check handlers.missing_cell {
    $nx eval {
        list [catch MOM_start_of_program m] [string match "redpost: MOM_start_of_program: *none.xml*" $m]
    }
} {1 1}
interp delete $nx

# NX's events that redpost refuses (issue 29, "Errors in NX terms"): each stops the post with the
# event, the operation and the reason, and nothing is written. The cycles' errors come from the
# expansion, which runs on NX's own thread: at the event itself. A motion's come from the
# session's thread: at a later event.
set bad_events {
    nan_goto {
        array set mom_mcs_goto {0 -100 1 NaN 2 110}
        MOM_linear_move
        MOM_end_of_program
    } {MOM_linear_move (reported at MOM_end_of_program) in operation OP1 (event 4 of the run):\
        *:4: a move with a coordinate that is not a finite number}
    tap {
        MOM_tap
    } {MOM_tap in operation OP1: this cycle is not supported*}
    csys {
        array set mom_csys_matrix {0 1 1 0 2 0 3 0 4 1 5 0 6 0 7 0 8 1 9 0 10 0 11 50}
        MOM_set_csys
    } {MOM_set_csys in operation OP1: a coordinate system other than the MCS*}
    cycle_without_depth {
        set mom_cycle_rapid_to 3
        MOM_drill
        MOM_end_of_program
    } {MOM_drill in operation OP1 (event 4 of the run): *:4: CYCLE/DRILL needs FEDTO*}
    hole_without_cycle {
        MOM_drill_move
        MOM_end_of_program
    } {MOM_drill_move in operation OP1 (event 4 of the run): *:4: a hole of a drilling cycle,\
        but no cycle is on*}
    css {
        MOM_spindle_css
    } {MOM_spindle_css in operation OP1: constant surface speed is not supported*}
    krl_insert {
        set mom_Instruction "KRL: LIN P1"
        MOM_insert
        MOM_end_of_program
    } {MOM_insert (reported at MOM_end_of_program) in operation OP1 (event 4 of the run):\
        *:4: 'LIN P1' cannot be passed to the KRL program*}
}
foreach {name script pattern} $bad_events {
    file mkdir $work/nx_bad_$name
    set nx [nx_interp $work/nx_bad_$name "variable cell [list $cell]; variable program_name BAD;\
        variable output_dir [list $work/nx_bad_$name]; variable source part.prt"]
    check handlers.refused.$name {
        $nx eval {
            MOM_start_of_program
            set mom_path_name OP1
            MOM_start_of_path
            array set mom_tool_axis {0 0 1 0 2 1}
            array set mom_mcs_goto {0 -120 1 -440 2 110}
            set mom_motion_type RAPID; set mom_motion_event rapid_move
            MOM_initial_move
        }
        set refused [catch {$nx eval $script} message]
        list $refused [string match "redpost: $pattern" $message] \
            [expr {$message eq [lindex [$nx eval {set ::aborted}] 0]}] \
            [glob -nocomplain -directory $work/nx_bad_$name *.src *.dat]
    } {1 1 1 {}}
    interp delete $nx
}

# An inch post: refused at the start, before anything is opened.
file mkdir $work/nx_inch
set nx [nx_interp $work/nx_inch "variable cell [list $cell]; variable program_name INCH;\
    variable output_dir [list $work/nx_inch]"]
check handlers.refused.inches {
    $nx eval {
        set mom_output_unit IN
        list [catch MOM_start_of_program m] [string match "*mom_output_unit IN*metric*" $m]
    }
} {1 1}
interp delete $nx

# --- nx_replay.tcl against `redpost convert`, byte for byte ----------------------------------------

set tclsh [info nameofexecutable]
set cases {
    pocket_arcs krc4_lin pocket_arcs.apt {--fit-tol 0}
    pocket_arcs_spline krc4_spline pocket_arcs.apt {--fit-tol 0}
    pocket_arcs_krc2 krc2_lin pocket_arcs.apt {--clearance 100 --fit-tol 0}
    surface_5axis krc4_lin surface_5axis.cls {--fit-tol 0}
    long_pass krc4_lin long_pass.apt {--split 150 --fit-tol 0}
    surface_5axis_fit krc4_lin surface_5axis.cls {}
    long_pass_fit krc4_spline long_pass.apt {}
    surface_fit_opts krc4_lin surface_5axis.cls {--fit-tol 0.05 --fit-ang-tol 0.5 --joints-csv JOINTS}
    long_pass_opts krc4_lin long_pass.apt {--apo 1 --cl-line-every 7 --base BASE_DATA[3] --tool TOOL_DATA[2]}
    surface_csv krc4_lin surface_5axis.cls {--joints-csv JOINTS}
}
foreach {name set input extra} $cases {
    set a $work/convert/$name
    set b $work/replay/$name
    file mkdir $a $b
    set prog [string toupper $name]
    set ea [string map [list JOINTS $a/joints.csv] $extra]
    set eb [string map [list JOINTS $b/joints.csv] $extra]
    check replay.$name.convert {
        exec -ignorestderr -- $redpost convert $cl/$input --cell $cell --krl $krl/$set.xml -o $a --name $prog -q {*}$ea
        set _ ok
    } ok
    check replay.$name.replay {
        exec -ignorestderr -- $tclsh $src/tcl/nx_replay.tcl --lib $libdir --cell $cell --krl $krl/$set.xml -o $b \
            --name $prog -q {*}$eb $cl/$input
        set _ ok
    } ok
    check replay.$name.identical {same_dirs $a $b} same
}
# The committed golden files too (they are what `redpost convert` must give).
foreach name {pocket_arcs pocket_arcs_spline pocket_arcs_krc2 surface_5axis long_pass
    surface_5axis_fit long_pass_fit} {
    check replay.$name.golden {same_dirs $src/tests/golden/$name $work/replay/$name} same
}
# Default program name and template set: made from the input's name, as convert does.
foreach input {pocket_arcs.apt surface_5axis.cls} {
    set a $work/convert_default/$input
    set b $work/replay_default/$input
    file mkdir $a $b
    check replay.default_name.$input {
        exec -ignorestderr -- $redpost convert $cl/$input --cell $cell -o $a -q
        exec -ignorestderr -- $tclsh $src/tcl/nx_replay.tcl --lib $libdir --cell $cell -o $b -q $cl/$input
        same_dirs $a $b
    } same
}

# Errors through the replay: the same file:line as convert, exit status 2, nothing written.
set f [open $work/far.apt w]
puts $f "PARTNO/FAR"
puts $f "RAPID"
puts $f "GOTO/-120,-440,110"
puts $f "FEDRAT/MMPM,1000"
puts $f "GOTO/5000,5000,110"
close $f
file mkdir $work/far_convert $work/far_replay
catch {exec $redpost convert $work/far.apt --cell $cell -o $work/far_convert -q} convert_message
set replay_failed [catch {
    exec $tclsh $src/tcl/nx_replay.tcl --lib $libdir --cell $cell -o $work/far_replay -q $work/far.apt
} replay_message options]
check replay.error.status {
    list $replay_failed [lindex [dict get $options -errorcode] 0] [lindex [dict get $options -errorcode] end]
} {1 CHILDSTATUS 2}
check replay.error.line {string match "*far.apt:5:*" $replay_message}
check replay.error.same_message {
    # convert: "error: <message>" or the message alone; the replay: "redpost: MOM_linear_move: <message>".
    regexp {far\.apt:5:.*} $convert_message cm
    regexp {far\.apt:5:.*} $replay_message rm
    expr {$cm eq $rm ? 1 : "convert: $cm / replay: $rm"}
}
check replay.error.no_output {glob -nocomplain -directory $work/far_replay *} {}

# --- result ------------------------------------------------------------------------------------------

puts "$passed passed, $failed failed"
exit [expr {$failed > 0}]
