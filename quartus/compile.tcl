# quartus_sh -t compile.tcl <top> <sv-file>: set the design, compile (map, fit, assemble) and time it.
package require ::quartus::project
package require ::quartus::flow
set top [lindex $argv 0]
set sv [lindex $argv 1]
project_open reducer_load -revision reducer_load
set_global_assignment -name TOP_LEVEL_ENTITY $top
remove_all_global_assignments -name SYSTEMVERILOG_FILE
set_global_assignment -name SYSTEMVERILOG_FILE $sv
export_assignments
execute_flow -compile
project_close
