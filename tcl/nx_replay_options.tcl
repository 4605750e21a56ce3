# nx_replay_options.tcl: the command line of nx_replay.tcl (the options of `redpost convert`,
# docs/convert.md) and the handlers' settings made from it. Sourced by nx_replay.tcl.

proc usage {{message ""}} {
    if {$message ne ""} {
        puts stderr "nx_replay: $message"
    }
    puts stderr "usage: tclsh nx_replay.tcl --cell CELL.xml -o OUTDIR \[--krl SET\] \[--name PROG\]\
        \[--joints-csv FILE\] \[--report FILE.html\] \[--placement x,y,z,a,b,c\] \[--base EXPR\]\
        \[--tool EXPR\] \[--tools FILE\] \[--msys ignore|apply\] \[--clearance Z\]\
        \[--rapid-vel M/S\] \[--max-bytes N\] \[--apo MM\] \[--split N\] \[--cl-line-every N\]\
        \[--chordal-tol MM\] \[--plan global|local\] \[--preset smooth|stiff|fast\]\
        \[--keyframe-spacing MM\] \[--lock E1=500 ...\] \[--predict-deflection\] \[--compensate\]\
        \[--cutting FILE\] \[--deflection-tol MM\] \[--fit-tol MM\] \[--fit-ang-tol DEG\]\
        \[--threads N\] \[--fixture F.stl\] \[--part F.stl\] \[--collision-margin MM\]\
        \[--lib DIR\] \[--post POST.tcl\] \[-q\] INPUT"
    exit 1
}

# Options with a value, and the settings they set (docs/nx-integration.md, "The settings").
array set option_setting {
    --cell cell --krl krl -o output_dir --output output_dir --name program_name
    --joints-csv joints_csv --report report --placement placement --base base --tool tool
    --tools tools --msys msys --clearance clearance --rapid-vel rapid_vel --max-bytes max_bytes
    --apo apo --split split --cl-line-every cl_line_every --chordal-tol chordal_tol --plan plan
    --preset preset --keyframe-spacing keyframe_spacing --cutting cutting
    --deflection-tol deflection_tol --fit-tol fit_tol --fit-ang-tol fit_ang_tol --threads threads
    --lib lib
    --lock lock --post post --fixture fixture --part part --collision-margin collision_margin
}

array set opt {quiet 0 lock {} fixture {} predict_deflection 0 compensate 0}
set input ""
for {set i 0} {$i < $argc} {incr i} {
    set a [lindex $argv $i]
    if {[info exists option_setting($a)]} {
        if {$i + 1 >= $argc} {
            usage "$a needs a value"
        }
        set key $option_setting($a)
        set value [lindex $argv [incr i]]
        if {$key in {lock fixture}} {
            lappend opt($key) $value
        } else {
            set opt($key) $value
        }
        continue
    }
    switch -- $a {
        -q - --quiet { set opt(quiet) 1 }
        --predict-deflection { set opt(predict_deflection) 1 }
        --compensate { set opt(compensate) 1 }
        -h - --help { usage }
        default {
            if {[string match -* $a] || $input ne ""} {
                usage "unexpected argument '$a'"
            }
            set input $a
        }
    }
}
if {$input eq "" || ![info exists opt(output_dir)] ||
        (![info exists opt(cell)] && ![info exists opt(post)])} {
    usage "INPUT, --cell (or --post) and -o are required"
}
foreach {key allowed} {msys {ignore apply} plan {global local} preset {smooth stiff fast}} {
    if {[info exists opt($key)] && $opt($key) ni $allowed} {
        usage "--[string map {_ -} $key]: $opt($key) not in {[join $allowed ,]}"
    }
}
if {[info exists opt(lib)]} {
    set auto_path [linsert $auto_path 0 [file normalize $opt(lib)]]
}

# The handlers' settings (redpost_settings.tcl) from the command line, with convert's defaults
# for what it does not give. Paths are taken as given (no settings folder), as convert takes them.
# With --post, the post's settings stay but for what the command line gives, its paths made
# absolute (the post's settings are relative to its own folder).
proc replay_settings {} {
    if {[info exists ::opt(post)]} {
        set ::redpost_settings::source $::input
        foreach key [array names ::opt] {
            if {$key ni {quiet lib post predict_deflection compensate lock fixture} ||
                    ($key in {lock fixture} && [llength $::opt($key)])} {
                set value $::opt($key)
                if {$key in {cell output_dir joints_csv report tools cutting part} ||
                        ($key eq "krl" && [string match */* $value])} {
                    set value [file normalize $value]
                } elseif {$key eq "fixture"} {
                    set value [lmap f $value {file normalize $f}]
                }
                set ::redpost_settings::$key $value
            }
        }
        foreach key {predict_deflection compensate} {
            if {$::opt($key)} {
                set ::redpost_settings::$key 1
            }
        }
        return
    }
    namespace eval ::redpost_settings {
        variable dir ""
        variable source $::input
        variable part_comment 1
        variable tool "TOOL_DATA\[1\]"
        foreach {name value} {krl "" program_name "" joints_csv "" report "" placement {}
            base "" tools "" clearance "" rapid_vel 0.25 max_bytes 0 apo 0.5 split 0
            cl_line_every 50 chordal_tol 0.01 msys ignore plan global preset smooth
            keyframe_spacing 20 cutting "" deflection_tol 0.05 fit_tol 0.01 fit_ang_tol 0.1
            threads 1 fixture {} part "" collision_margin 5} {
            variable $name $value
        }
    }
    foreach key [array names ::opt] {
        switch -- $key {
            quiet - lib - post {}
            placement {
                set p [split $::opt(placement) ,]
                if {[llength $p] != 6} {
                    usage "--placement takes six numbers x,y,z,a,b,c (mm and deg),\
                        got '$::opt(placement)'"
                }
                set ::redpost_settings::placement $p
            }
            default {
                set ::redpost_settings::$key $::opt($key)
            }
        }
    }
}
