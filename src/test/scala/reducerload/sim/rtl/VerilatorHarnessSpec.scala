package reducerload.sim.rtl

import reducerload.testutil.CompiledParams
import reducerload.testutil.Scratch
import org.scalatest.flatspec.AnyFlatSpec
import reducerload.app.{Emit, Top}
import reducerload.arm.ArmModel
import reducerload.graph.SampleCodes
import reducerload.config.LoadParams
import reducerload.load.LoadChecks
import reducerload.testutil.{Golden, Seeds}

import scala.jdk.CollectionConverters._
import scala.sys.process._
import scala.util.{Random, Try}

/**
 * The compiled Verilator harness on the load datapath: bit-exact with the model on the golden traces and on
 * random, out-of-range and extreme codes, ready/valid honoured with a shared CORDIC unit, and the build
 * cached. Needs Verilator (CI always has it).
 */
class VerilatorHarnessSpec extends AnyFlatSpec {
  behavior of "VerilatorHarness"

  private def verilatorPresent: Boolean = Try(
    Seq("verilator", "--version").!!(ProcessLogger(_ => ()))
  ).isSuccess

  private def emitted(p: LoadParams) =
    Emit.emit(Emit.bare(reducerload.compiler.Compiler.compile(p, "test")), Top.Load, "test")

  /**
   * Golden traces, then seeded random samples (1 in 8 beyond the declared ranges), then every port at its
   * extreme codes.
   */
  private def samples(p: LoadParams, label: String, seed: Long, randomCount: Int): IndexedSeq[SampleCodes] = {
    val model = new LoadChecks.Joint3Model(p)
    val rng = new Random(Seeds(label, seed))
    val golden = Golden.all.flatMap(_.samples.map(model.encode))
    val random = Seq.fill(randomCount) {
      model.encode(
        if (rng.nextInt(8) == 0) LoadChecks.outOfRangeSample(p.robot, rng)
        else LoadChecks.randomSample(p.robot, rng)
      )
    }
    val ports = ArmHarnessPorts(p.arm).inputs
    def at(pick: HarnessPort => BigInt) = {
      val v = ports.map(pick)
      SampleCodes(v.slice(0, 3).toIndexedSeq, v.slice(3, 6).toIndexedSeq, v.slice(6, 9).toIndexedSeq)
    }
    (golden ++ random ++ Seq(
      at(_.minValue),
      at(_.maxValue),
      at(q => if (q.signed) q.minValue else q.maxValue)
    )).toIndexedSeq
  }

  private def codes(p: LoadParams, out: IndexedSeq[BigInt]) =
    ArmHarnessPorts.codes(out, p.arm.graph.outputs.size)

  private def checkBitExact(
      label: String,
      p: LoadParams,
      in: IndexedSeq[SampleCodes],
      r: HarnessResult
  ): Unit = {
    val model = new ArmModel(p.arm)
    assert(r.outputs.size == in.size, s"$label: ${r.outputs.size} outputs for ${in.size} samples")
    assert(r.acceptedCycles.size == in.size)
    val wrong = in.indices.filter(i => codes(p, r.outputs(i)) != model.evaluate(in(i)))
    assert(
      wrong.isEmpty,
      s"$label: ${wrong.size} outputs differ from the model, first at sample ${wrong.headOption.getOrElse(-1)}: " +
        wrong.headOption.map(i => s"${r.outputs(i)} vs ${model.evaluate(in(i))}").getOrElse("")
    )
    // Fixed latency: each output appears exactly `latency` clocks after its sample was taken.
    val latency = p.arm.latency
    assert(
      in.indices.forall(i => r.outputCycles(i) == r.acceptedCycles(i) + latency),
      s"$label: an output is not $latency clocks after its sample"
    )
  }

  it should "reproduce the bit-accurate model on the golden traces, random, out-of-range and extreme codes (default preset)" in {
    assume(verilatorPresent, "verilator is not installed")
    val p = LoadParams.default
    val in = samples(p, "harness-default", 31L, 20000)
    val harness = VerilatorHarness.compile(emitted(p).verilog, p.arm.moduleName, ArmHarnessPorts(p.arm))
    val r = harness.run(in.map(ArmHarnessPorts.values), samplePeriod = 1, drainCycles = p.arm.latency + 1)
    checkBitExact("default", p, in, r)
    // One sample per clock: taken on consecutive cycles from cycle 0.
    assert(r.acceptedCycles == in.indices.map(_.toLong))
    val flagged = r.outputs.count(o => codes(p, o).outOfRange.exists(identity))
    assert(flagged > 0, "no out-of-range sample was flagged")
    // The process's own CPU time: positive, and (one thread) not beyond its wall time by more than the clock's granularity.
    assert(
      r.stats.cpuSeconds > 0 && r.stats.cpuSeconds <= r.stats.seconds + 0.05,
      s"harness CPU ${r.stats.cpuSeconds} s, wall ${r.stats.seconds} s"
    )
    println(
      f"[harness] default: ${in.size} samples bit-exact ($flagged flagged out of range), " +
        f"${r.stats.cycles} cycles, ${r.stats.samplesPerSecond}%.0f samples/s, ${r.stats.cyclesPerCpuSecond}%.0f clocks per CPU second " +
        f"(${if (harness.fromCache) "cached build" else "fresh build"})"
    )
  }

  it should "wait for ready with a shared CORDIC unit: samples offered every clock are taken every third (compact preset)" in {
    assume(verilatorPresent, "verilator is not installed")
    val p = LoadParams.compact
    assert(p.arm.schedule.clocksPerSample == 3)
    val in = samples(p, "harness-compact", 32L, 3000)
    val harness = VerilatorHarness.compile(emitted(p).verilog, p.arm.moduleName, ArmHarnessPorts(p.arm))
    val drain = p.arm.latency + 1
    // samplePeriod 1 offers a sample on every clock; io_in_ready is low two clocks out of three.
    val r = harness.run(in.map(ArmHarnessPorts.values), samplePeriod = 1, drainCycles = drain)
    checkBitExact("compact", p, in, r)
    val gaps = r.acceptedCycles.zip(r.acceptedCycles.tail).map { case (a, b) => b - a }.distinct
    assert(gaps == Seq(3L), s"samples were taken with gaps $gaps, expected every third clock")
    // A longer period than the design needs is honoured: samples 5 clocks apart or more, taken on the design's one-in-3 input clocks.
    val slow = harness.run(in.take(500).map(ArmHarnessPorts.values), samplePeriod = 5, drainCycles = drain)
    checkBitExact("compact, period 5", p, in.take(500), slow)
    assert(slow.acceptedCycles.zip(slow.acceptedCycles.tail).forall { case (a, b) =>
      b - a >= 5 && (b - a) % 3 == 0
    })
    // A stall limit shorter than the design's refusal fails loudly instead of hanging or dropping.
    val e = intercept[IllegalStateException](
      harness.run(
        in.take(10).map(ArmHarnessPorts.values),
        samplePeriod = 1,
        drainCycles = drain,
        maxStallCycles = 1
      )
    )
    assert(e.getMessage.contains("io_in_ready stayed low"), e.getMessage)
  }

  it should "reuse the cached build of the same design" in {
    assume(verilatorPresent, "verilator is not installed")
    val p = LoadParams.default
    val verilog = emitted(p).verilog
    val first = VerilatorHarness.compile(verilog, p.arm.moduleName, ArmHarnessPorts(p.arm))
    val start = System.nanoTime()
    val second = VerilatorHarness.compile(verilog, p.arm.moduleName, ArmHarnessPorts(p.arm))
    val seconds = (System.nanoTime() - start) / 1e9
    assert(second.fromCache, "the second compile of the same design was not a cache hit")
    assert(second.directory == first.directory)
    assert(second.directory.startsWith(VerilatorHarness.cacheRoot))
    assert(seconds < 5.0, f"a cache hit took $seconds%.1f s")
    Seq("harness.cpp", "design.sv", "build.log").foreach(f =>
      assert(java.nio.file.Files.exists(second.directory.resolve(f)), f)
    )
    println(f"[harness] cache hit in $seconds%.2f s: ${second.directory}")
  }

  it should "refuse a port description that does not match the design, and values that do not fit a port" in {
    val p = LoadParams.default
    val verilog = emitted(p).verilog
    val top = p.arm.moduleName
    val ports = ArmHarnessPorts(p.arm)
    def refused(words: String*)(f: => Any): Unit = {
      val e = intercept[IllegalArgumentException](f)
      words.foreach(w => assert(e.getMessage.contains(w), s"'${e.getMessage}' does not mention '$w'"))
    }
    val wrongWidth =
      ports.copy(inputs = ports.inputs.updated(0, ports.inputs(0).copy(width = ports.inputs(0).width + 1)))
    refused("io_in_bits_q_0", "bits wide")(VerilatorHarness.checkPorts(verilog, top, wrongWidth))
    refused("no port 'io_in_bits_t1'")(
      VerilatorHarness.checkPorts(
        verilog,
        top,
        ports.copy(inputs = ports.inputs :+ HarnessPort("io_in_bits_t1", 3, signed = false))
      )
    )
    refused("io_in_bits_qdd_2", "not in the harness description")(
      VerilatorHarness.checkPorts(verilog, top, ports.copy(inputs = ports.inputs.init))
    )
    refused("'io_in_ready' is an output")(
      VerilatorHarness.checkPorts(
        verilog,
        top,
        ports.copy(inReady = None, inputs = ports.inputs :+ HarnessPort("io_in_ready", 1, signed = false))
      )
    )
    refused("no module 'Nope'")(VerilatorHarness.checkPorts(verilog, "Nope", ports))
    refused("wide", "1 to 64 bits")(HarnessPort("io_wide", 65, signed = true))
    refused("named twice")(ports.copy(outputs = ports.outputs :+ ports.outputs.head))
    VerilatorHarness.checkPorts(verilog, top, ports) // the real description passes
    if (verilatorPresent) {
      val harness = VerilatorHarness.compile(verilog, top, ports)
      val tooBig = Seq.fill(9)(BigInt(0)).updated(3, ports.inputs(3).maxValue + 1)
      refused("io_in_bits_qd_0", "does not fit")(harness.run(Seq(tooBig)))
      refused("9 input ports")(harness.run(Seq(Seq(BigInt(1)))))
    }
  }

  /**
   * A small design written the way firtool writes ports: 64-bit unsigned and signed inputs, a 5-bit signed
   * one, a one-clock registered result, and ready low every other clock.
   */
  private val tinyVerilog =
    """// Hand-written harness test design.
      |module Tiny(
      |  input         clock,
      |                reset,
      |  output        io_in_ready,
      |  input         io_in_valid,
      |  input  [63:0] io_in_bits_u,
      |                io_in_bits_s,
      |  input  [4:0]  io_in_bits_c,
      |  output        io_out_valid,
      |  output [63:0] io_out_bits_u,
      |                io_out_bits_sum,
      |  output [4:0]  io_out_bits_negC
      |);
      |  reg        ready;
      |  reg        valid;
      |  reg [63:0] u, sum;
      |  reg [4:0]  negC;
      |  always @(posedge clock) begin
      |    if (reset) begin
      |      ready <= 1'h0;
      |      valid <= 1'h0;
      |    end else begin
      |      ready <= ~ready;
      |      valid <= io_in_valid & ready;
      |    end
      |    u <= io_in_bits_u;
      |    sum <= io_in_bits_s + {{59{io_in_bits_c[4]}}, io_in_bits_c};
      |    negC <= 5'h0 - io_in_bits_c;
      |  end
      |  assign io_in_ready = ready;
      |  assign io_out_valid = valid;
      |  assign io_out_bits_u = u;
      |  assign io_out_bits_sum = sum;
      |  assign io_out_bits_negC = negC;
      |endmodule
      |""".stripMargin

  private val tinyPorts = HarnessPorts(
    inputs = Seq(
      HarnessPort("io_in_bits_u", 64, signed = false),
      HarnessPort("io_in_bits_s", 64, signed = true),
      HarnessPort("io_in_bits_c", 5, signed = true)
    ),
    inValid = "io_in_valid",
    inReady = Some("io_in_ready"),
    outValid = "io_out_valid",
    outputs = Seq(
      HarnessPort("io_out_bits_u", 64, signed = false),
      HarnessPort("io_out_bits_sum", 64, signed = true),
      HarnessPort("io_out_bits_negC", 5, signed = true)
    )
  )

  it should "carry 1- to 64-bit signed and unsigned values exactly, and build once when two compiles race on an empty cache" in {
    assume(verilatorPresent, "verilator is not installed")
    import scala.concurrent.{Await, Future}
    import scala.concurrent.ExecutionContext.Implicits.global
    import scala.concurrent.duration._
    val cache = Scratch.dir("harness-cache-")
    try {
      val racing = Seq.fill(2)(Future(VerilatorHarness.compile(tinyVerilog, "Tiny", tinyPorts, cache)))
      val Seq(a, b) = racing.map(Await.result(_, 10.minutes))
      assert(a.directory == b.directory)
      val entries = java.nio.file.Files.list(cache)
      try
        assert(
          entries.iterator().asScala.map(_.getFileName.toString).toSeq == Seq(
            a.directory.getFileName.toString
          ),
          "leftovers in the cache"
        )
      finally entries.close()
      assert(VerilatorHarness.compile(tinyVerilog, "Tiny", tinyPorts, cache).fromCache)

      val rng = new Random(Seeds("harness-tiny", 33L))
      val u64 = BigInt(1) << 64
      val edges = Seq(
        Seq(u64 - 1, BigInt(Long.MinValue), BigInt(-1)),
        Seq(BigInt(0), BigInt(Long.MaxValue) - 15, BigInt(15)),
        Seq(BigInt(Long.MaxValue) + 1, BigInt(-1), BigInt(-16))
      )
      val in = edges ++ Seq.fill(2000)(
        Seq(BigInt(64, rng), BigInt(64, rng) - (BigInt(1) << 63), BigInt(rng.nextInt(32) - 16))
      )
      def wrapSigned(v: BigInt, w: Int) = {
        val m = v.mod(BigInt(1) << w); if (m.testBit(w - 1)) m - (BigInt(1) << w) else m
      }
      val r = a.run(in, samplePeriod = 1, drainCycles = 2)
      assert(r.outputs == in.map(s => IndexedSeq(s(0), wrapSigned(s(1) + s(2), 64), wrapSigned(-s(2), 5))))
      // Ready is high every other clock: the harness held each sample until it was taken.
      assert(r.acceptedCycles.zip(r.acceptedCycles.tail).forall { case (x, y) => y - x == 2 })
      assert(r.outputCycles == r.acceptedCycles.map(_ + 1))
    } finally VerilatorHarness.deleteTree(cache)
  }
}
