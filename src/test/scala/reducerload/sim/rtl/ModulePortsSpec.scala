package reducerload.sim.rtl

import reducerload.regmap.{ReducerLoadRegisters, WrapperPorts}

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.app.{Cli, Emission, Emit, Simulate, Top}
import reducerload.arm.ArmIO
import reducerload.cordic.CordicSinCosIO
import reducerload.monitor.MonitoredArmIO
import reducerload.testutil.monitoredPlanar3

/**
 * The ports derived from a module's IO Bundle are the emitted Verilog's, name, direction, width and order:
 * the arm datapath, the arm with its reducer monitor, and the lone sin/cos unit.
 */
class ModulePortsSpec extends AnyFlatSpec {
  behavior of "ModulePorts"

  private def params(args: String*) = Cli.parse("simulate", args, Simulate.options, Simulate.flags).compiled

  private def inVerilog(e: Emission) =
    VerilogPortList(e.verilog, e.topModule).map(v => (v.name, v.direction, v.width))

  private def derived(ports: ModulePorts) = ports.all.map { p =>
    (p.name, if (p.direction == PortDirection.In) "input" else "output", p.width)
  }

  it should "name every port of planar3's datapath and monitored arm, and of the sin/cos unit, as firtool does" in {
    val plain = params("--robot", "planar3")
    val arm = plain.arm
    assert(derived(ModulePorts(new ArmIO(arm))) == inVerilog(Emit.emit(Emit.bare(plain), Top.Load, "test")))

    val monitored = params(monitoredPlanar3: _*)
    val io = new MonitoredArmIO(monitored.arm, monitored.monitor.get)
    val ports = ModulePorts(io)
    assert(derived(ports) == inVerilog(Emit.emit(Emit.bare(monitored), Top.Load, "test")))
    assert(ports(io.host.readAddress).name == "io_host_readAddress")
    // The wrappers' port lists (report, packaging) as firtool names them.
    def wrapper(c: reducerload.compiler.Compiled, bus: reducerload.config.BusKind) = {
      val ports = bus match {
        case reducerload.config.BusKind.Axi => WrapperPorts.axi(c.arm, ReducerLoadRegisters(c))
        case _                              => WrapperPorts.avalon(c.arm, ReducerLoadRegisters(c))
      }
      val e = Emit.emit(c.copy(config = c.config.copy(bus = c.config.bus.copy(kind = bus))), Top.Load, "test")
      assert(
        ports.map(p => (p.name, if (p.direction == "in") "input" else "output", p.width)) == inVerilog(e),
        s"${bus.name} wrapper ports"
      )
    }
    wrapper(monitored, reducerload.config.BusKind.Avalon)
    wrapper(plain, reducerload.config.BusKind.Axi)
    assert(
      ports(io.in.bits.q(2)) == ModulePort("io_in_bits_q_2", PortDirection.In, arm.numerics.angleBits, false)
    )
    val harness = ArmHarnessPorts(io)
    assert(harness.held.map(_.name) == Seq("io_host_snapshot", "io_host_clear", "io_host_readAddress"))
    assert(harness.inReady.contains("io_in_ready") && harness.outValid == "io_out_valid")
    // A stimulus run drives the host port the harness otherwise holds at 0, and reads it back.
    assert(
      harness.host.map(h => Seq(h.snapshot, h.clear, h.readAddress.name, h.readData.name, h.snapshotDone)) ==
        Some(
          Seq(
            "io_host_snapshot",
            "io_host_clear",
            "io_host_readAddress",
            "io_host_readData",
            "io_host_snapshotDone"
          )
        )
    )
    assert(ArmHarnessPorts(new reducerload.arm.ArmIO(monitored.arm)).host.isEmpty)

    val lone = params()
    assert(
      derived(ModulePorts(new CordicSinCosIO(lone.config.cordic))) == inVerilog(
        Emit.emit(lone, Top.SinCos, "test")
      )
    )
  }
}
