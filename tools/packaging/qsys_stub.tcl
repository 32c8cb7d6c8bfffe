# Platform Designer's component commands as stubs, so a generated <top>_hw.tcl runs under a plain tclsh:
#
#     tclsh tools/packaging/qsys_stub.tcl generated/reducer_load_hw.tcl
#
# Each stub checks its argument count and prints one tab-separated line: the command and its arguments.
# PackagingSpec compares those declarations with the emitted Verilog's ports. A command the file uses and
# this list lacks fails ("invalid command name"), as would an unknown command in Platform Designer.

rename package _package
proc package {args} {
    if {[lrange $args 0 1] eq {require -exact} && [lindex $args 2] eq "qsys"} {
        record package qsys [lindex $args 3]
        return
    }
    uplevel 1 [list _package {*}$args]
}

proc record {args} { puts [join $args "\t"] }

# name, then the argument counts Platform Designer accepts.
foreach {name counts} {
    set_module_property    {2}
    add_fileset            {2 3 4}
    set_fileset_property   {3}
    add_fileset_file       {4 5}
    add_interface          {3 4}
    set_interface_property {3}
    add_interface_port     {5}
} {
    proc $name {args} [string map [list @NAME@ $name @COUNTS@ $counts] {
        if {[llength $args] ni {@COUNTS@}} {
            error "@NAME@: [llength $args] arguments ($args); expected @COUNTS@"
        }
        record @NAME@ {*}$args
    }]
}

if {$argc != 1} {
    puts stderr "usage: tclsh qsys_stub.tcl COMPONENT_hw.tcl"
    exit 1
}
source [lindex $argv 0]
