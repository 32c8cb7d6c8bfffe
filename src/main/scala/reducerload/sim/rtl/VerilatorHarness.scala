package reducerload.sim.rtl

import java.nio.charset.StandardCharsets
import java.nio.file.{FileSystemException, Files, Path, Paths, StandardCopyOption}
import java.security.MessageDigest
import scala.jdk.CollectionConverters._
import scala.sys.process._
import scala.util.Try

/**
 * A compiled C++ Verilator testbench for bulk simulation: the design streams samples from a binary file and
 * writes its outputs to another, with no JVM round trip per clock (chiseltest's peek/poke costs tens of
 * microseconds per cycle). Builds are cached by content, so a second run of the same design starts at once.
 */
object VerilatorHarness {

  /**
   * Reset clocks before the first sample: enough for a synchronous reset to reach every register it drives.
   */
  val resetCycles = 4

  /**
   * Verilator's options. -Wno-fatal: the emitted design has lint warnings that CI waives in lint/waivers.vlt
   * (-Wall); a build is not a lint. The `SignedMultiply` black box is inline in the emitted file, so it needs
   * nothing more. `--prefix Vtop` keeps the C++ class name independent of the top module's name. OPT_FAST=-O2
   * compiles the model for speed (Verilator's default is -Os).
   */
  val verilatorFlags: Seq[String] = Seq(
    "--cc",
    "--exe",
    "--build",
    "-O3",
    "--x-assign",
    "fast",
    "--x-initial",
    "fast",
    "--noassert",
    "-Wno-fatal",
    "-Wno-lint",
    "-Wno-style",
    "--prefix",
    "Vtop",
    "-MAKEFLAGS",
    "OPT_FAST=-O2"
  )

  /** `$XDG_CACHE_HOME/reducer-load-harness`, or `~/.cache/reducer-load-harness`. */
  def cacheRoot: Path = {
    val base = sys.env
      .get("XDG_CACHE_HOME")
      .filter(_.nonEmpty)
      .map(Paths.get(_))
      .getOrElse(Paths.get(sys.props("user.home"), ".cache"))
    base.resolve("reducer-load-harness")
  }

  /** `verilator --version`, or a clear error when Verilator is missing. */
  def verilatorVersion(): String =
    Try(Seq("verilator", "--version").!!(ProcessLogger(_ => ())).trim).getOrElse(
      throw new IllegalStateException(
        "the Verilator harness needs verilator on the PATH (Debian: apt-get install verilator)"
      )
    )

  /** Whether `verilator` runs on this machine. */
  def available: Boolean = Try(verilatorVersion()).isSuccess

  /** Executable name inside a cache entry. */
  private[sim] val executableName = "harness"

  /**
   * Compile `verilog` (the whole design in one text, as `Emit.emit` returns it) with a harness for `top` and
   * `ports`, or reuse the cached build of the same inputs. The port description is checked against the
   * module's port list first. `cache` is where builds are kept (tests and benchmarks pass an empty directory
   * to force a fresh build).
   */
  def compile(verilog: String, top: String, ports: HarnessPorts, cache: Path = cacheRoot): CompiledHarness = {
    checkPorts(verilog, top, ports)
    val cpp = cppSource(top, ports)
    val version = verilatorVersion()
    val key = sha256(Seq(verilog, cpp, version, verilatorFlags.mkString(" ")).mkString("\u0000"))
    val root = cache.toAbsolutePath.normalize
    val entry = root.resolve(key)
    val cached = Files.isExecutable(entry.resolve(executableName))
    if (!cached) build(root, entry, verilog, cpp, top)
    new CompiledHarness(entry.resolve(executableName), ports, fromCache = cached)
  }

  private def sha256(text: String): String =
    MessageDigest
      .getInstance("SHA-256")
      .digest(text.getBytes(StandardCharsets.UTF_8))
      .map(b => f"${b & 0xff}%02x")
      .mkString

  /**
   * Every described port must exist in `top` with the right direction and width, and every data input must be
   * driven.
   */
  private[sim] def checkPorts(verilog: String, top: String, ports: HarnessPorts): Unit = {
    val declared = VerilogPortList(verilog, top).map(p => p.name -> p).toMap
    def check(name: String, direction: String, width: Int): Unit = {
      val p = declared.getOrElse(
        name,
        throw new IllegalArgumentException(
          s"module '$top' has no port '$name' (ports: ${declared.keys.toSeq.sorted.mkString(", ")})"
        )
      )
      require(
        p.direction == direction,
        s"module '$top': port '$name' is an ${p.direction}, the harness description says $direction"
      )
      require(
        p.width == width,
        s"module '$top': port '$name' is ${p.width} bits wide, the harness description says $width"
      )
    }
    Seq(ports.clock, ports.reset, ports.inValid).foreach(check(_, "input", 1))
    ports.inReady.foreach(check(_, "output", 1))
    check(ports.outValid, "output", 1)
    ports.inputs.foreach(p => check(p.name, "input", p.width))
    ports.outputs.foreach(p => check(p.name, "output", p.width))
    ports.held.foreach(p => check(p.name, "input", p.width))
    ports.host.foreach { h =>
      check(h.readData.name, "output", h.readData.width)
      check(h.snapshotDone, "output", 1)
    }
    val undriven = declared.values.filter(_.direction == "input").map(_.name).toSet -- ports.allNames
    require(
      undriven.isEmpty,
      s"module '$top': input(s) ${undriven.toSeq.sorted.mkString(", ")} are not in the harness description"
    )
  }

  /**
   * Build into a private temporary directory, then rename the finished entry into place: a concurrent build
   * of the same design either wins the rename or finds the entry complete, and a crashed build leaves only a
   * `.tmp-` directory behind, never a half-written entry.
   */
  private def build(root: Path, entry: Path, verilog: String, cpp: String, top: String): Unit = {
    Files.createDirectories(root)
    removeStaleTemporaries(root)
    val tmp = Files.createTempDirectory(root, ".tmp-")
    try {
      val src = Files.createDirectories(tmp.resolve("src"))
      val obj = tmp.resolve("obj_dir")
      Files.write(src.resolve("design.sv"), verilog.getBytes(StandardCharsets.UTF_8))
      Files.write(src.resolve("harness.cpp"), cpp.getBytes(StandardCharsets.UTF_8))
      val jobs = Runtime.getRuntime.availableProcessors.max(1)
      val command = Seq("verilator") ++ verilatorFlags ++ Seq(
        "-j",
        jobs.toString,
        "--top-module",
        top,
        "-Mdir",
        obj.toString,
        "-o",
        executableName,
        src.resolve("design.sv").toString,
        src.resolve("harness.cpp").toString
      )
      val log = new StringBuilder
      val status = Process(command, tmp.toFile).!(
        ProcessLogger(l => log.append(l).append('\n'), l => log.append(l).append('\n'))
      )
      Files.write(src.resolve("build.log"), log.toString.getBytes(StandardCharsets.UTF_8))
      if (status != 0 || !Files.isExecutable(obj.resolve(executableName))) {
        val tail = log.toString.linesIterator.toSeq.takeRight(30).mkString("\n")
        throw new IllegalStateException(
          s"Verilator harness build failed (exit $status): ${command.mkString(" ")}\n$tail"
        )
      }
      // The entry keeps the executable and its sources (for debugging), not the object files.
      Files.move(obj.resolve(executableName), src.resolve(executableName))
      try Files.move(src, entry, StandardCopyOption.ATOMIC_MOVE)
      catch {
        // Another process finished the same build first (rename(2) onto its non-empty directory
        // fails, reported as a plain FileSystemException): its entry is complete, use it.
        case _: FileSystemException if Files.isExecutable(entry.resolve(executableName)) => ()
      }
    } finally deleteTree(tmp)
  }

  /** `.tmp-` directories older than a day are left by killed builds; nobody else is using them. */
  private def removeStaleTemporaries(root: Path): Unit = {
    val dayAgo = System.currentTimeMillis() - 24L * 3600 * 1000
    val listing = Files.list(root)
    try
      listing
        .iterator()
        .asScala
        .toSeq
        .filter(p =>
          p.getFileName.toString.startsWith(".tmp-") && Try(Files.getLastModifiedTime(p).toMillis < dayAgo)
            .getOrElse(false)
        )
        .foreach(p => Try(deleteTree(p)))
    finally listing.close()
  }

  private[reducerload] def deleteTree(dir: Path): Unit =
    if (Files.exists(dir)) {
      val walk = Files.walk(dir)
      try walk.iterator().asScala.toSeq.reverse.foreach(p => Files.deleteIfExists(p))
      finally walk.close()
    }

  /** The C++ testbench for `top` and `ports` (see its header comment for the file formats). */
  def cppSource(top: String, ports: HarnessPorts): String = {
    require(HarnessPorts.identifier.matches(top), s"top module '$top' is not an identifier")
    def mask(w: Int) = if (w == 64) "~uint64_t(0)" else s"((uint64_t(1) << $w) - 1)"
    val drives = ports.inputs.zipWithIndex
      .map { case (p, i) =>
        s"      drive(top->${p.name}, uint64_t(s[$i]) & ${mask(p.width)});  // ${p.width} bits, ${if (p.signed) "signed"
          else "unsigned"}"
      }
      .mkString("\n")
    val records = ports.outputs.zipWithIndex
      .map { case (p, i) =>
        val read = s"static_cast<uint64_t>(top->${p.name})"
        if (p.signed) s"      record[${i + 1}] = signExtend($read, ${p.width});"
        else s"      record[${i + 1}] = static_cast<int64_t>($read);"
      }
      .mkString("\n")
    val ready = ports.inReady.map(r => s"top->$r").getOrElse("true")
    // The stimulus run's output records: cycle, tag, then the outputs.
    val observed = ports.outputs.zipWithIndex
      .map { case (p, i) =>
        val read = s"static_cast<uint64_t>(top->${p.name})"
        if (p.signed) s"      record[${i + 2}] = signExtend($read, ${p.width});"
        else s"      record[${i + 2}] = static_cast<int64_t>($read);"
      }
      .mkString("\n")
    val hostDrive = ports.host.fold("    (void)what;  // no host port") { h =>
      s"""    top->${h.snapshot} = (what >> 2) & 1;
         |    top->${h.clear} = (what >> 3) & 1;
         |    drive(top->${h.readAddress.name}, (what & 16) ? (uint64_t(what) >> 32) & ${mask(
          h.readAddress.width
        )} : 0);""".stripMargin
    }
    val hostDone = ports.host.fold("") { h =>
      s"""
         |    if (top->${h.snapshotDone}) put(cycle, 2, nullptr, 0);""".stripMargin
    }
    val hostRead = ports.host.fold(
      "    if (what & 16) fail(\"a read in STIMULUS, and the design has no host port\", argv[3]);"
    ) { h =>
      s"""    if (what & 16) {
         |      const int64_t data = static_cast<int64_t>(static_cast<uint64_t>(top->${h.readData.name}));
         |      put(cycle, 3, &data, 1);
         |    }""".stripMargin
    }
    s"""// Generated by reducerload.sim.rtl.VerilatorHarness (reducer-load generator). Do not edit.
       |// Top module: $top
       |// Inputs (one record per sample):  ${ports.inputs.map(_.name).mkString(", ")}
       |// Outputs (one record per valid):  cycle, ${ports.outputs.map(_.name).mkString(", ")}
       |//
       |// Drives samples from INPUTS into the ready/valid input ${ports.inValid}/${ports.inReady.getOrElse(
        "(always ready)"
      )}:
       |// a sample is offered (valid high) once SAMPLE_PERIOD clocks have passed since the previous one
       |// was taken, and held until valid && ready at a rising edge. Every cycle with ${ports.outValid}
       |// high appends the outputs to OUTPUTS; every taken sample appends its cycle to ACCEPTED.
       |// Files are little-endian int64, signed outputs sign-extended. After the last sample, DRAIN_CYCLES
       |// more clocks run. Prints the counts and the process's CPU seconds. Exit status 2 with one line on
       |// stderr on any error.
       |// Usage: harness INPUTS OUTPUTS ACCEPTED SAMPLE_PERIOD DRAIN_CYCLES MAX_STALL_CYCLES
       |//
       |// Stimulus run (a separate loop, so the stream above stays as it is):
       |//   harness --stimulus INPUTS STIMULUS OBSERVED CYCLES
       |// STIMULUS: records (cycle, what) of int64, cycles increasing; a clock without one is quiet. Bits of
       |// what: 0 one more sample of INPUTS is available, 1 reset, 2 snapshot, 3 clear, 4 read (address in
       |// bits 32 and up). The next available sample is offered whenever none is held, and held (valid high,
       |// data unchanged) until valid && ready at a rising edge; valid is low while reset is high.
       |// OBSERVED: records (cycle, tag, payload): tag 0 a sample taken, 1 outputs valid (payload: the
       |// outputs), 2 snapshotDone high, 3 the read data of the clock's address one clock later (payload).
       |// Runs CYCLES clocks after the reset.
       |#include <cerrno>
       |#include <cstdint>
       |#include <cstdio>
       |#include <cstdlib>
       |#include <cstring>
       |#include <ctime>
       |#include <memory>
       |#include <vector>
       |
       |#include "verilated.h"
       |#include "Vtop.h"
       |
       |namespace {
       |constexpr int kInputs = ${ports.inputs.size};
       |constexpr int kOutputs = ${ports.outputs.size};
       |constexpr int kResetCycles = $resetCycles;
       |constexpr size_t kChunk = 8192;  // samples read per fread
       |
       |[[noreturn]] void fail(const char* what, const char* detail) {
       |  std::fprintf(stderr, "harness: %s%s%s\\n", what, detail ? ": " : "", detail ? detail : "");
       |  std::exit(2);
       |}
       |
       |// Port members are references of CData/SData/IData/QData; the caller masks to the port width.
       |template <typename T>
       |inline void drive(T& port, uint64_t value) { port = static_cast<T>(value); }
       |
       |inline int64_t signExtend(uint64_t value, int width) {
       |  return width >= 64 ? static_cast<int64_t>(value)
       |                     : static_cast<int64_t>(value << (64 - width)) >> (64 - width);
       |}
       |
       |long long argument(const char* text, const char* name) {
       |  char* end = nullptr;
       |  errno = 0;
       |  const long long v = std::strtoll(text, &end, 10);
       |  if (errno != 0 || *end != '\\0' || v < 0) fail("not a non-negative integer", name);
       |  return v;
       |}
       |
       |// Reset with valid low and the held host inputs at 0; the clock ends low, ready for the first rising edge.
       |void reset(Vtop& top) {
       |  top.${ports.clock} = 0;
       |  top.${ports.reset} = 1;
       |  top.${ports.inValid} = 0;${ports.held.map(h => s"\n  top.${h.name} = 0;  // held").mkString}
       |  top.eval();
       |  for (int i = 0; i < kResetCycles; ++i) {
       |    top.${ports.clock} = 1;
       |    top.eval();
       |    top.${ports.clock} = 0;
       |    top.eval();
       |  }
       |  top.${ports.reset} = 0;
       |}
       |
       |FILE* open(const char* path, const char* mode) {
       |  FILE* f = std::fopen(path, mode);
       |  if (f == nullptr) fail("cannot open", path);
       |  return f;
       |}
       |
       |int stimulusRun(char** argv) {
       |  const long long cycles = argument(argv[5], "CYCLES");
       |  FILE* in = open(argv[2], "rb");
       |  FILE* stimulus = open(argv[3], "rb");
       |  FILE* observed = open(argv[4], "wb");
       |  std::vector<char> inBuffer(1 << 20), stimulusBuffer(1 << 20), observedBuffer(1 << 20);
       |  std::setvbuf(in, inBuffer.data(), _IOFBF, inBuffer.size());
       |  std::setvbuf(stimulus, stimulusBuffer.data(), _IOFBF, stimulusBuffer.size());
       |  std::setvbuf(observed, observedBuffer.data(), _IOFBF, observedBuffer.size());
       |  int64_t record[2 + kOutputs];
       |  auto put = [&](long long cycle, int64_t tag, const int64_t* payload, int n) {
       |    record[0] = cycle;
       |    record[1] = tag;
       |    for (int i = 0; i < n; ++i) record[2 + i] = payload[i];
       |    if (std::fwrite(record, sizeof(int64_t), 2 + n, observed) != size_t(2 + n)) fail("write error", argv[4]);
       |  };
       |  int64_t event[2];
       |  auto nextEvent = [&]() {
       |    const size_t got = std::fread(event, sizeof event, 1, stimulus);
       |    if (got != 1 && std::ferror(stimulus)) fail("read error", argv[3]);
       |    return got == 1;
       |  };
       |
       |  auto context = std::make_unique<VerilatedContext>();
       |  auto top = std::make_unique<Vtop>(context.get());
       |  reset(*top);
       |
       |  int64_t sample[kInputs];
       |  bool haveEvent = nextEvent(), holding = false;
       |  long long available = 0, taken = 0, produced = 0, cycle = 0;
       |  for (; cycle < cycles; ++cycle) {
       |    int64_t what = 0;
       |    if (haveEvent && event[0] < cycle) fail("STIMULUS cycles must increase", argv[3]);
       |    if (haveEvent && event[0] == cycle) {
       |      what = event[1];
       |      haveEvent = nextEvent();
       |    }
       |    if (what & 1) ++available;
       |    if (!holding && available > 0) {
       |      if (std::fread(sample, sizeof sample, 1, in) != 1) fail("INPUTS has fewer samples than STIMULUS offers", argv[2]);
       |      --available;
       |      holding = true;
       |      const int64_t* s = sample;
       |$drives
       |    }
       |    const bool reset = (what & 2) != 0;
       |    top->${ports.clock} = 0;
       |    top->${ports.reset} = reset;
       |    top->${ports.inValid} = holding && !reset;
       |$hostDrive
       |    top->eval();
       |    if (top->${ports.outValid}) {
       |      record[0] = cycle;
       |      record[1] = 1;
       |$observed
       |      if (std::fwrite(record, sizeof record, 1, observed) != 1) fail("write error", argv[4]);
       |      ++produced;
       |    }$hostDone
       |    if (holding && !reset && $ready) {
       |      put(cycle, 0, nullptr, 0);
       |      holding = false;
       |      ++taken;
       |    }
       |    top->${ports.clock} = 1;  // rising edge
       |    top->eval();
       |$hostRead
       |  }
       |  if (haveEvent) fail("STIMULUS has records at or after CYCLES", argv[3]);
       |  top->final();
       |  if (std::fclose(observed) != 0) fail("write error", argv[4]);
       |  std::fclose(stimulus);
       |  std::fclose(in);
       |  std::printf("cycles=%lld samples=%lld outputs=%lld cpu_seconds=%.6f\\n", cycle, taken, produced,
       |              static_cast<double>(std::clock()) / CLOCKS_PER_SEC);
       |  return 0;
       |}
       |}  // namespace
       |
       |int main(int argc, char** argv) {
       |  if (argc == 6 && std::strcmp(argv[1], "--stimulus") == 0) return stimulusRun(argv);
       |  if (argc != 7) fail("usage", "harness INPUTS OUTPUTS ACCEPTED SAMPLE_PERIOD DRAIN_CYCLES MAX_STALL_CYCLES");
       |  const uint16_t probe = 1;
       |  if (*reinterpret_cast<const uint8_t*>(&probe) != 1) fail("big-endian hosts are not supported", nullptr);
       |  const long long period = argument(argv[4], "SAMPLE_PERIOD");
       |  const long long drain = argument(argv[5], "DRAIN_CYCLES");
       |  const long long maxStall = argument(argv[6], "MAX_STALL_CYCLES");
       |  if (period < 1) fail("SAMPLE_PERIOD must be >= 1", argv[4]);
       |
       |  FILE* in = open(argv[1], "rb");
       |  std::fseek(in, 0, SEEK_END);
       |  const long size = std::ftell(in);
       |  std::fseek(in, 0, SEEK_SET);
       |  if (size < 0 || size % long(sizeof(int64_t) * kInputs) != 0) fail("INPUTS is not a whole number of samples", argv[1]);
       |  FILE* out = open(argv[2], "wb");
       |  FILE* accepted = open(argv[3], "wb");
       |  std::vector<char> outBuffer(1 << 20), acceptedBuffer(1 << 20);
       |  std::setvbuf(out, outBuffer.data(), _IOFBF, outBuffer.size());
       |  std::setvbuf(accepted, acceptedBuffer.data(), _IOFBF, acceptedBuffer.size());
       |
       |  auto context = std::make_unique<VerilatedContext>();
       |  auto top = std::make_unique<Vtop>(context.get());
       |
       |  reset(*top);
       |
       |  std::vector<int64_t> samples(kChunk * kInputs);
       |  size_t have = 0, next = 0;
       |  bool inputDone = false;
       |  int64_t record[1 + kOutputs];
       |  long long cycle = 0, lastTaken = -period, stalled = 0, drainLeft = drain, taken = 0, produced = 0;
       |  for (;;) {
       |    if (next == have && !inputDone) {
       |      have = std::fread(samples.data(), sizeof(int64_t) * kInputs, kChunk, in);
       |      next = 0;
       |      if (std::ferror(in)) fail("read error", argv[1]);
       |      if (have == 0) inputDone = true;
       |    }
       |    const bool pending = next < have;
       |    if (!pending && drainLeft == 0) break;
       |
       |    // Before the rising edge: inputs for this cycle (the clock falls in the same evaluation).
       |    const bool offer = pending && cycle - lastTaken >= period;
       |    top->${ports.clock} = 0;
       |    top->${ports.inValid} = offer;
       |    if (offer) {
       |      const int64_t* s = &samples[next * kInputs];
       |$drives
       |    }
       |    top->eval();
       |    const bool fire = offer && $ready;
       |    if (top->${ports.outValid}) {
       |      record[0] = cycle;
       |$records
       |      if (std::fwrite(record, sizeof record, 1, out) != 1) fail("write error", argv[2]);
       |      ++produced;
       |    }
       |    if (fire) {
       |      const int64_t at = cycle;
       |      if (std::fwrite(&at, sizeof at, 1, accepted) != 1) fail("write error", argv[3]);
       |      ++next;
       |      ++taken;
       |      lastTaken = cycle;
       |      stalled = 0;
       |    } else if (offer && ++stalled > maxStall) {
       |      fail("${ports.inReady.getOrElse(
        "ready"
      )} stayed low for MAX_STALL_CYCLES clocks with a sample offered", argv[6]);
       |    }
       |    if (!pending) --drainLeft;
       |
       |    top->${ports.clock} = 1;  // rising edge: registers take this cycle's inputs
       |    top->eval();
       |    ++cycle;
       |  }
       |  top->final();
       |  if (std::fclose(out) != 0) fail("write error", argv[2]);
       |  if (std::fclose(accepted) != 0) fail("write error", argv[3]);
       |  std::fclose(in);
       |  std::printf("cycles=%lld samples=%lld outputs=%lld cpu_seconds=%.6f\\n", cycle, taken, produced,
       |              static_cast<double>(std::clock()) / CLOCKS_PER_SEC);
       |  return 0;
       |}
       |""".stripMargin
  }
}
