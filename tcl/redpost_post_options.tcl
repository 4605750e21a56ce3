# redpost_post_options.tcl: the session options of the redpost NX handlers (redpost_post.tcl),
# made from the settings (redpost_settings.tcl) with the names and meanings of `redpost
# convert`'s options (docs/nx-integration.md, "The settings"). Sourced by redpost_post.tcl.

namespace eval ::redpost_post {

    # A path from the settings: relative to the settings file's directory.
    # An absolute path, or one given with no settings folder (nx_replay.tcl: as on its command
    # line), stays as it is.
    proc setting_path {value} {
        if {$value eq "" || $::redpost_settings::dir eq "" ||
                [file pathtype $value] eq "absolute"} {
            return $value
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
        if {[string length $name] > 19} {
            tell "redpost warning: the program name '[string range $name 0 18]' is NX's output\
                file's name cut to 19 characters; set program_name to choose it"
        }
        return [string range $name 0 18]
    }

    # A setting that must be a whole number of at least `least`.
    proc whole_setting {name least} {
        set v [set ::redpost_settings::$name]
        if {![string is wide -strict $v] || $v < $least} {
            error "the setting $name is '$v': it must be a whole number of at least $least"
        }
        return $v
    }

    # A variable of the settings, or `default` where an older settings file has none.
    proc setting {name {default ""}} {
        if {[info exists ::redpost_settings::$name]} {
            return [set ::redpost_settings::$name]
        }
        return $default
    }

    # The session options from the settings and NX's output file, as `redpost convert` makes
    # them from its command line.
    proc open_options {} {
        if {[string toupper [mom mom_output_unit MM]] in {IN INCH}} {
            error "the post outputs inches (mom_output_unit IN): redpost takes mm; set the\
                postprocessor's output unit to metric"
        }
        set output_file [mom mom_output_file_full_name]
        set dir [setting output_dir]
        if {$dir eq ""} {
            set dir [expr {$output_file ne "" ? [file dirname $output_file] : [pwd]}]
        }
        set name [setting program_name]
        if {$name eq ""} {
            if {$output_file eq ""} {
                error "no program name: set program_name in redpost_settings.tcl"
            }
            set name [program_name_from $output_file]
        }
        set src [setting source]
        if {$src eq ""} {
            set src [expr {[mom mom_part_name] ne "" ? [mom mom_part_name] : $output_file}]
        }
        set max_bytes [setting max_bytes 0]
        if {$max_bytes ne "0" && $max_bytes ne ""} {
            set max_bytes [whole_setting max_bytes 16384]
        }
        set tol [setting deflection_tol 0.05]
        if {![string is double -strict $tol] || $tol < 1e-6 || $tol > 100} {
            error "the setting deflection_tol is '$tol': it must be 1e-06 to 100 mm"
        }
        set opts [list -cell [setting_path [setting cell]] -output [setting_path $dir] \
                      -name $name -base [setting base] -tool [setting tool TOOL_DATA\[1\]] \
                      -apo [setting apo 0.5] -split [whole_setting split 0] \
                      -cl-line-every [whole_setting cl_line_every 0] \
                      -chordal-tol [setting chordal_tol 0.01] -clearance [setting clearance] \
                      -rapid-vel [setting rapid_vel 0.25] -max-bytes $max_bytes \
                      -msys [setting msys ignore] -plan [setting plan global] \
                      -preset [setting preset smooth] \
                      -keyframe-spacing [setting keyframe_spacing 20] -lock [setting lock] \
                      -deflection-tol $tol -pipeline [setting pipeline 1] \
                      -fit-tol [setting fit_tol 0.01] -fit-ang-tol [setting fit_ang_tol 0.1] \
                      -threads [setting threads 1] \
                      -collision-margin [setting collision_margin 5]]
        # The set-up's STL files, relative to the settings file as every path is.
        set fixtures {}
        foreach f [setting fixture] {
            lappend fixtures [setting_path $f]
        }
        if {[llength $fixtures]} {
            lappend opts -fixture $fixtures
        }
        # --cutting alone asks for the prediction, --compensate implies it (as in convert).
        set cutting [setting cutting]
        if {[setting compensate 0]} {
            lappend opts -deflection compensate
        } elseif {[setting predict_deflection 0] || $cutting ne ""} {
            lappend opts -deflection predict
        }
        foreach {setting option} {tools -tools joints_csv -joints-csv report -report
            cutting -cutting part -part} {
            if {[setting $setting] ne ""} {
                lappend opts $option [setting_path [setting $setting]]
            }
        }
        if {[setting krl] ne ""} {
            lappend opts -krl [krl_path [setting krl]]
        }
        if {[llength [setting placement]]} {
            lappend opts -placement [setting placement]
        }
        if {$src ne ""} {
            lappend opts -source $src
        }
        return $opts
    }
}
