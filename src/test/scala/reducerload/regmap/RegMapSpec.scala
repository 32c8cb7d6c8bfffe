package reducerload.regmap

import org.scalatest.flatspec.AnyFlatSpec
import reducerload.app.{Cli, Emit, Main}
import reducerload.compiler.Compiled
import reducerload.monitor.RegisterMap
import reducerload.testutil.{Scratch, Seeds}

import java.nio.charset.StandardCharsets
import java.nio.file.{Files, Path, Paths}
import scala.jdk.CollectionConverters._
import scala.sys.process._
import scala.util.{Random, Try}

/** The monitored planar arm the register-map tests use (docs/register-map.md's example). */
object RegMapDesign {
  val args: Seq[String] = reducerload.app.RegisterMapDoc.exampleArgs
  lazy val compiled: Compiled = Cli.parse("emit", args, Emit.options).compiled
  lazy val map: CsrMap = ReducerLoadRegisters(compiled)

  /** C macro names, as the header spells them (written here again: the test must not trust the emitter). */
  def cMacro(parts: String*): String = ("RL" +: parts).mkString("_").toUpperCase
}

/** Runs a C program: compile with gcc and the given flags (failing the test if it does not), run it. */
object CProgram {
  def available: Boolean = Try(Seq("gcc", "--version").!!(ProcessLogger(_ => ()))).isSuccess

  /** The program's exit status and standard output. */
  def run(dir: Path, source: String, flags: Seq[String]): (Int, String) = {
    val c = dir.resolve("check.c")
    Files.write(c, source.getBytes(StandardCharsets.UTF_8))
    val exe = dir.resolve("check")
    val log = new StringBuilder
    val cmd = Seq("gcc") ++ flags ++ Seq("-I", dir.toString, "-o", exe.toString, c.toString)
    val status = cmd.!(ProcessLogger(l => log.append(l).append('\n'), l => log.append(l).append('\n')))
    require(status == 0, s"${cmd.mkString(" ")} failed:\n$log")
    val out = new StringBuilder
    val exit =
      Seq(exe.toString).!(ProcessLogger(l => out.append(l).append('\n'), l => out.append(l).append('\n')))
    (exit, out.toString)
  }
}

/**
 * The register map described once and what is generated from it: the layout rule, `run emit`'s three files
 * with their regeneration command, the C header under gcc's strictest C99, and the SystemRDL through PeakRDL
 * (systemrdl-compiler and peakrdl-cheader from PyPI), whose header must agree with ours on every register
 * offset and field.
 */
class RegMapSpec extends AnyFlatSpec {
  behavior of "the register map"

  import RegMapDesign.{cMacro, map}

  it should "place each block at a multiple of its span, the monitor block word for word as the monitor's bank" in {
    val m = RegMapDesign.compiled.monitor.get
    // Expected from the rule, by hand: 64-word minimum spans for the small blocks; the monitor's span is
    // its bank rounded up to a power of two.
    val monitorSpan = Integer.highestOneBit(m.registerMap.words - 1) * 2
    val expectedBases =
      Seq("id" -> 0, "ctrl" -> 64, "counters" -> 128, "irq" -> 192, "payload" -> 256, "sample" -> 320) :+
        ("monitor" -> ((384 + monitorSpan - 1) / monitorSpan * monitorSpan))
    assert(map.blocks.map(b => b.block.name -> b.base) == expectedBases)
    assert(map.block("payload").registers.isEmpty, "the payload block is reserved, not filled")
    val monitor = map.block("monitor")
    val monitorWords = m.registerMap.entries.flatMap(e => (0 until e.words).map(w => e.address + w))
    assert(monitor.registers.map(_.word - monitor.base) == monitorWords)
    assert(monitor.registers.head.register.reset == RegisterMap.idBase + 3)
    assert(map.registers.map(_.byteOffset).distinct.size == map.registers.size)
    assert(map.words >= monitor.base + monitorSpan && Integer.bitCount(map.words) == 1)
    val id = map.block("id").registers.map(r => r.register.name -> r.register.reset).toMap
    assert(id("magic") == BigInt("524C4F44", 16) && (id("shape") & 0xff) == 3)
  }

  it should "describe the payload and sample blocks of a payload design without the monitor, addresses kept" in {
    val c = ReducerLoadTopDesigns.ur5Payloaded
    val m = ReducerLoadRegisters(c)
    // Same bases as with the monitor; no monitor block; the irq block reserved.
    assert(
      m.blocks.map(b => b.block.name -> b.base) ==
        Seq("id" -> 0, "ctrl" -> 64, "counters" -> 128, "irq" -> 192, "payload" -> 256, "sample" -> 320)
    )
    assert(m.block("irq").registers.isEmpty)
    assert(m.register("ctrl_control").register.fields.map(_.name) == Seq("clear_counters"))
    assert(m.registers.forall(_.register.source != Source.Status))
    // One RW register per parameter, in numerics.parameters' order, then commit and sequence.
    val payload = m.block("payload").registers.map(_.register)
    val expectedNames = reducerload.arm.PayloadColumns.names ++ Seq("gravity_x", "gravity_y", "gravity_z")
    val port = c.arm.numerics.parameterPortFormat
    assert(port.width <= 32, "the UR5's parameters take one word each")
    assert(payload.map(_.name) == expectedNames ++ Seq("commit", "sequence"))
    assert(payload.take(13).map(_.source) == (0 until 13).map(Source.Parameter(_, 0)))
    payload.take(13).foreach { r =>
      val f = r.fields.head
      assert(f.access == Access.ReadWrite && f.signed && f.width == port.width)
      assert(f.format.isInstanceOf[FieldFormat.Fixed])
    }
    // Reset: no payload, the elaboration gravity (-9.81 along one axis) as two's complement.
    val gz = payload.find(_.name == "gravity_z").get.fields.head
    val gravity = payload.slice(10, 13).map(_.fields.head.reset)
    assert(payload.take(10).forall(_.reset == 0) && gravity.exists(_ != 0), gravity)
    assert(gz.reset.bitLength <= port.width)
    // Sample block: q, qd, qdd of each joint at consecutive words, then start, status, tau, flags, sequence.
    val sample = m.block("sample")
    val names = sample.registers.map(_.register.name)
    val joints = c.arm.chain.size
    // The UR5's torques are wider than 32 bits: word 0 of every joint, then word 1 of every joint.
    assert(c.arm.analysis.outputPortFormat.width > 32)
    Seq("q_j", "qd_j", "qdd_j", "tau_j%d_w0", "tau_j%d_w1").foreach { k =>
      val name = if (k.contains("%d")) (j: Int) => k.format(j) else (j: Int) => s"$k$j"
      val words = (1 to joints).map(j => sample.registers.find(_.register.name == name(j)).get.word)
      assert(words == (words.head until words.head + joints), s"$k: $words")
    }
    val top = sample.registers.find(_.register.name == "tau_j1_w1").get.register.fields.head
    assert(top.signed && top.width == 32)
    assert(
      names.takeRight(2) == Seq("flags", "sequence") && names.contains("start") && names.contains("status")
    )
    assert(CHeader(m, "test").contains(s"#define RL_JOINTS $joints"))
  }

  it should "be written by run emit beside the Verilog, each file headed by its regeneration command" in {
    val d = Scratch.dir("regmap-emit-")
    Main.run(Seq("emit") ++ RegMapDesign.args ++ Seq("--target-dir", d.toString))
    val listing = Files.list(d).iterator().asScala.map(_.getFileName.toString).toSet
    val files = Seq(
      "reducer_load_regs.h",
      "reducer_load_regs.md",
      "reducer_load_regs.rdl",
      "reducer_load_layout.h",
      "reducer_load_hw.tcl"
    )
    assert(files.forall(listing), listing)
    val sv = listing.find(_.endsWith(".sv")).get
    val command =
      new String(Files.readAllBytes(d.resolve(sv)), StandardCharsets.UTF_8).linesIterator.drop(1).next()
    assert(command.contains("./sbt \"run emit"), command)
    files.foreach { f =>
      val text = new String(Files.readAllBytes(d.resolve(f)), StandardCharsets.UTF_8)
      assert(text.contains(command.stripPrefix("//").trim), s"$f lacks the regeneration command")
    }
  }

  it should "give a C header that gcc compiles as strict C99, with every offset, field and SI scale described" in {
    assume(CProgram.available, "gcc is not installed")
    val seed = Seeds("RegMapSpec C header", 32)
    val rnd = new Random(seed)
    val d = Scratch.dir("regmap-c-")
    Files.write(d.resolve("reducer_load_regs.h"), CHeader(map, "test").getBytes(StandardCharsets.UTF_8))
    // Every register and field: offset, reset, mask, shift, width; plus seeded codes of fixed-point fields
    // converted with the header's scale.
    val fixed = map.registers.flatMap(r =>
      r.register.fields.collect { case f @ Field(_, _, _, _, _, FieldFormat.Fixed(format, _), _, _) =>
        (r, f, format)
      }
    )
    val codes = fixed.map { case (r, f, format) =>
      (r, f, format, BigInt(format.width - 1, rnd.self) - (if (rnd.nextBoolean()) format.maxRaw else 0))
    }
    val prints = map.registers.flatMap { r =>
      val n = cMacro(r.cName)
      s"""printf("%s %lu %lu\\n", "${r.cName}", (unsigned long)${n}_OFFSET, (unsigned long)${n}_RESET);""" +:
        r.register.fields.map { f =>
          val fn = s"${n}_${f.name.toUpperCase}"
          s"""printf("%s.%s %lu %u %u\\n", "${r.cName}", "${f.name}", (unsigned long)${fn}_MASK, """ +
            s"(unsigned)${fn}_SHIFT, (unsigned)${fn}_WIDTH);"
        }
    } ++ codes.map { case (r, f, _, code) =>
      s"""printf("si %s.%s %.17g\\n", "${r.cName}", "${f.name}", ${code}.0 * ${cMacro(
          r.cName,
          f.name
        )}_SCALE);"""
    } ++ map.ports.map(p => s"""printf("port %s %.17g\\n", "${p.name}", ${cMacro("port", p.name)}_SCALE);""")
    val program =
      (Seq("#include <stdio.h>", "#include \"reducer_load_regs.h\"", "int main(void) {") ++ prints.map(
        "  " + _
      ) ++
        Seq("  return 0;", "}")).mkString("", "\n", "\n")
    val (status, text) = CProgram.run(d, program, Seq("-std=c99", "-Wall", "-Wextra", "-Werror", "-pedantic"))
    assert(status == 0, text)
    val out = text.linesIterator.toSeq
    val expected = map.registers.flatMap { r =>
      s"${r.cName} ${r.byteOffset} ${r.register.reset}" +: r.register.fields.map { f =>
        s"${r.cName}.${f.name} ${((BigInt(1) << f.width) - 1) << f.lsb} ${f.lsb} ${f.width}"
      }
    }
    assert(out.take(expected.size) == expected)
    val si = out.drop(expected.size)
    codes.zip(si).foreach { case ((r, f, format, code), line) =>
      assert(line.startsWith(s"si ${r.cName}.${f.name} "))
      assert(line.split(' ').last.toDouble == format.toDouble(code), s"$line: code $code of $format")
    }
    val n = RegMapDesign.compiled.arm.numerics
    val portScales = si.drop(codes.size).map(_.split(' ')).map(a => a(1) -> a(2).toDouble).toMap
    assert(portScales("qd") == math.pow(2.0, -n.velocityPortFormat.fracBits))
    assert(portScales("q") == 2 * math.Pi / math.pow(2.0, n.angleBits))
  }

  it should "give SystemRDL that PeakRDL compiles into a header agreeing with ours on every register and field" in {
    assume(CProgram.available, "gcc is not installed")
    val d = Scratch.dir("regmap-rdl-")
    val rdl = d.resolve("reducer_load_regs.rdl")
    Files.write(rdl, SystemRdl(map, "test").getBytes(StandardCharsets.UTF_8))
    Files.write(d.resolve("reducer_load_regs.h"), CHeader(map, "test").getBytes(StandardCharsets.UTF_8))
    val script =
      Paths.get(sys.env.getOrElse("REDUCERLOAD_CWD", ".")).resolve("tools/regmap/peakrdl_header.py")
    val log = new StringBuilder
    val status = Seq("python3", script.toString, rdl.toString, d.resolve("peakrdl.h").toString)
      .!(
        ProcessLogger(
          l => { println(l); log.append(l).append('\n') },
          l => { println(l); log.append(l).append('\n') }
        )
      )
    if (status == 3) {
      val reason =
        "the package index is unreachable: PeakRDL cannot be installed, the SystemRDL check is skipped"
      println(s"RegMapSpec: $reason")
      cancel(reason)
    }
    assert(status == 0, s"PeakRDL refused the SystemRDL:\n$log")
    val peak = new String(Files.readAllBytes(d.resolve("peakrdl.h")), StandardCharsets.UTF_8)
    assert(
      "(?m)^// reg - ".r.findAllMatchIn(peak).size == map.registers.size,
      "PeakRDL sees another register count"
    )
    val struct = "reducer_load_regs_t"
    val checks = map.registers.flatMap { r =>
      val ours = cMacro(r.cName)
      val theirs = s"REDUCER_LOAD_REGS__${r.cName.toUpperCase}"
      s"CHECK(offsetof($struct, ${r.cName}) == ${ours}_OFFSET);" +: r.register.fields.flatMap { f =>
        val (o, t) = (s"${ours}_${f.name.toUpperCase}", s"${theirs}__${f.name.toUpperCase}")
        Seq(
          s"CHECK(${t}_bm == ${o}_MASK);",
          s"CHECK(${t}_bp == ${o}_SHIFT);",
          s"CHECK(${t}_bw == ${o}_WIDTH);"
        ) ++
          (if (peak.contains(s"#define ${t}_reset ")) Seq(s"CHECK(${t}_reset == ${o}_RESET);") else Nil)
      }
    }
    val program = (Seq(
      "#include <stdio.h>",
      "#include <stddef.h>",
      "#include \"peakrdl.h\"",
      "#include \"reducer_load_regs.h\"",
      "static int failures = 0, checked = 0;",
      "#define CHECK(x) do { checked++; if (!(x)) { failures++; printf(\"disagree: %s\\n\", #x); } } while (0)",
      "int main(void) {"
    ) ++ checks.map("  " + _) ++ Seq(
      s"  CHECK(sizeof($struct) <= RL_MAP_BYTES);",
      "  printf(\"checked %d, failed %d\\n\", checked, failures);",
      "  return failures != 0;",
      "}"
    )).mkString("", "\n", "\n")
    val (exit, out) = CProgram.run(d, program, Seq("-std=c11", "-Wall", "-Werror"))
    println(s"RegMapSpec: PeakRDL agreement: ${out.linesIterator.toSeq.last}")
    assert(exit == 0 && out.trim == s"checked ${checks.size + 1}, failed 0", out)
  }

  it should "give an Avalon slave whose own module passes Verilator lint -Wall with the project's waivers" in {
    assume(Try(Seq("verilator", "--version").!!).isSuccess, "verilator is not installed")
    val c = RegMapDesign.compiled
    val verilog = Emit.withBlackBoxes(
      circt.stage.ChiselStage.emitSystemVerilog(
        new ReducerLoadAvalon(c.arm, c.monitor, map, "reducer_load"),
        Array.empty[String],
        Emit.firtoolOpts
      )
    )
    val d = Scratch.dir("regmap-lint-")
    val sv = d.resolve("reducer_load.sv")
    Files.write(sv, verilog.getBytes(StandardCharsets.UTF_8))
    val top = "reducer_load"
    val log = new StringBuilder
    val status =
      Seq("verilator", "--lint-only", "-Wall", "--top-module", top, "lint/waivers.vlt", sv.toString)
        .!(ProcessLogger(l => log.append(l).append('\n'), l => log.append(l).append('\n')))
    // The new module's own lines; what it instantiates is the monitored arm, linted on its own terms
    // (EmitSpec), so its warnings are printed, not failed here.
    val lines = verilog.linesIterator.toIndexedSeq
    val first = lines.indexWhere(_.startsWith(s"module $top(")) + 1
    val last = lines.indexWhere(_.startsWith("endmodule"), first) + 1
    val warning = """%Warning-[A-Z]+: [^:]*reducer_load\.sv:(\d+):.*""".r
    val (own, others) = log.toString.linesIterator
      .collect { case l @ warning(line) => (line.toInt, l) }
      .toSeq
      .partition { case (line, _) => line >= first && line <= last }
    others.foreach { case (_, l) => println(s"RegMapSpec: lint outside $top: $l") }
    assert(first > 0 && last >= first, s"no module $top in the Verilog")
    assert(own.isEmpty, s"verilator lint of $top (lines $first-$last):\n${own.map(_._2).mkString("\n")}")
    assert(status == 0 || others.nonEmpty, s"verilator lint failed for $top:\n$log")
  }
}
