package reducerload.monitor

import chisel3._
import chisel3.util.{Cat, Log2, Valid}
import reducerload.fixedpoint.FixedHw
import reducerload.pipeline.{MultiplierImpl, PipelinedMultiplier}

/**
 * One joint of [[ReducerMonitor]]: the per-sample pipeline, the live state and its shadow.
 *
 * Stages (cycles after the input): 1 input registers; 2 magnitudes |tau|, |qd|; 3 the power table's region
 * (leading one of |tau|) and the constant comparisons (T_R, T_M, bin edges); 4 the normalising shift; 5 the
 * table read (base, delta, shift); then the interpolation multiply, the mantissa register, the |qd| x
 * mantissa multiply (both `PipelinedMultiplier`s: registered 18x18 blocks) and the shift by the segment's
 * exponent (registered). Everything is delayed to `p.updateStage`, where one clock applies clear, the sample
 * and snapshot exactly as [[MonitorModel.step]] does. Data registers carry no reset; the valid and command
 * bits and the state do.
 */
class JointMonitor(p: MonitorParams, j: Int, liveFlags: Boolean = false)(implicit
    multiplierImpl: MultiplierImpl
) extends Module {
  override def desiredName = s"JointMonitor_${p.jointNames(j)}"
  val io = IO(new Bundle {
    val in = Flipped(Valid(new MonitorJointSample(p, j)))
    val snapshot = Input(Bool())
    val clear = Input(Bool())
    val shadow = Output(new JointMonitorState(p, j))
    // The live state's flags (JointField.Flags' bits), for a bus wrapper's interrupt; absent by default, so
    // the monitor's Verilog is the same without it.
    val flags = if (liveFlags) Some(Output(UInt(JointField.FlagBit.count.W))) else None
  })
  private val (tf, vf, table) = (p.torqueFormats(j), p.velocityFormats(j), p.powerTables(j))
  private val update = p.updateStage

  /** Control bits: registered with reset, so no stale valid or command survives a reset. */
  private def controlDelay(x: Bool, n: Int): Bool = (0 until n).foldLeft(x)((v, _) => RegNext(v, false.B))

  /** Data from stage `at` to the update stage. */
  private def toUpdate[T <: Data](x: T, at: Int): T = FixedHw.delay(x, update - at)

  /**
   * \|x| in width - 1 bits; the most negative code saturates to the largest magnitude, like
   * [[MonitorParams.magnitude]].
   */
  private def magnitude(x: SInt): UInt = {
    val w = x.getWidth
    val negated = ((~x.asUInt).asUInt + 1.U)(w - 1, 0)
    val mostNegative = x === (-(BigInt(1) << (w - 1))).S(w.W)
    Mux(mostNegative, ((BigInt(1) << (w - 1)) - 1).U((w - 1).W), Mux(x(w - 1), negated, x.asUInt)(w - 2, 0))
  }

  // ---- stage 1: input registers ----
  private val valid1 = controlDelay(io.in.valid, 1)
  private val snapshot1 = controlDelay(io.snapshot, 1)
  private val clear1 = controlDelay(io.clear, 1)
  private val torque1 = FixedHw.delay(io.in.bits.torque, 1)
  private val velocity1 = FixedHw.delay(io.in.bits.velocity, 1)
  private val outOfRange1 = FixedHw.delay(io.in.bits.outOfRange, 1)

  // ---- stage 2: magnitudes ----
  private val tau2 = FixedHw.delay(torque1, 1)
  private val absTau2 = FixedHw.delay(magnitude(torque1), 1)
  private val absQd2 = FixedHw.delay(magnitude(velocity1), 1)
  private val outOfRange2 = FixedHw.delay(outOfRange1, 1)

  // ---- stage 3: region (leading one) and the comparisons with constants ----
  // Region r >= 1: the leading one at bit n-K+r-1; region 0: no one at or above bit n-K
  // (PowerTable.regionOf).
  private val n = table.codeBits
  private val octaveBits2 = absTau2(n - 1, n - table.octaves)
  private val region3 = FixedHw.delay(
    Mux(octaveBits2.orR, Log2(octaveBits2) +& 1.U, 0.U).pad(table.regionBits)(table.regionBits - 1, 0),
    1
  )
  private val absTau3 = FixedHw.delay(absTau2, 1)
  private val absTauSigned2 = absTau2.zext
  private val aboveRepeated3 = FixedHw.delay(FixedHw.greaterThan(absTauSigned2, p.repeatedPeakCode(j)), 1)
  private val aboveMomentary3 = FixedHw.delay(FixedHw.greaterThan(absTauSigned2, p.momentaryPeakCode(j)), 1)
  // Bin k: edge(k) <= |tau| < edge(k + 1), one-hot; "at least edge" is "greater than edge - 1".
  private val atLeastEdge2 =
    p.binEdges(j).map(e => if (e == 0) true.B else FixedHw.greaterThan(absTauSigned2, e - 1))
  private val bin3 = FixedHw.delay(
    VecInit(atLeastEdge2.indices.map { k =>
      if (k + 1 < atLeastEdge2.size) atLeastEdge2(k) && !atLeastEdge2(k + 1) else atLeastEdge2(k)
    }),
    1
  )

  // ---- stage 4: normalising shift sh(r) = K - max(r, 1) (PowerTable.normalisingShift; no bit leaves the n
  // bits) ----
  private val normalisingShift3 = Mux(region3 === 0.U, (table.octaves - 1).U, table.octaves.U - region3)
  // Registered: the k segment bits and the used offset bits (bits n-2 .. droppedBits; bit n-1 holds the
  // leading one).
  private val normal4 = FixedHw.delay((absTau3 << normalisingShift3)(n - 2, table.droppedBits), 1)
  private val region4 = FixedHw.delay(region3, 1)

  // ---- stage 5: table read (registered address and data: a ROM), segment = region 2^k + the k bits below
  // bit n-1 ----
  private val address4 = Cat(region4, normal4(n - 2 - table.droppedBits, table.usedOffsetBits))
  private val romWidth = table.baseBits + table.deltaBits + table.shiftBits
  // One ROM word per segment: base, delta, shift (high to low).
  private val rom = VecInit(table.base.indices.map { s =>
    ((table.base(s) << (table.deltaBits + table.shiftBits)) | (table.delta(s) << table.shiftBits) | BigInt(
      table.shift(s)
    )).U(romWidth.W)
  })
  private val word5 = FixedHw.delay(rom(address4), 1)
  private val base5 = word5(romWidth - 1, table.deltaBits + table.shiftBits)
  private val delta5 = word5(table.deltaBits + table.shiftBits - 1, table.shiftBits)
  private val shift5 = word5(table.shiftBits - 1, 0)
  private val offset5 = FixedHw.delay(normal4(table.usedOffsetBits - 1, 0), 1)

  // ---- interpolation: mantissa = base + delta * offset / 2^usedOffsetBits, rounded half up
  // (PowerTable.mantissa) ----
  private val (interpA, interpB) = p.interpolationMulWidths(j)
  private val interpolation = PipelinedMultiplier(delta5.zext, offset5.zext)
  require(interpolation.getWidth == interpA + interpB, "JointMonitor: interpolation product width")
  private val interpolationAt = 5 + PipelinedMultiplier.latency(interpA, interpB)
  // Rounded half up; the product is non-negative and the extra bit keeps the add from wrapping.
  private val step = ((interpolation.asUInt +& table.half.U) >> table.usedOffsetBits)
    .pad(table.baseBits)(table.baseBits - 1, 0)
  // Proven: base + step <= the segment's end point < 2^powerFracBits, so the sum keeps baseBits.
  private val mantissa = FixedHw.delay(FixedHw.delay(base5, interpolationAt - 5) +% step, 1)
  require(
    interpolationAt + 1 == p.powerReadyAt(j),
    "JointMonitor: schedule differs from MonitorParams.powerReadyAt"
  )

  // ---- damage increment (|qd| x mantissa) << shift: exact, registered ----
  private val (damageA, damageB) = p.damageMulWidths(j)
  private val damage = PipelinedMultiplier(FixedHw.delay(absQd2, p.powerReadyAt(j) - 2).zext, mantissa.zext)
  private val damageAt = p.powerReadyAt(j) + PipelinedMultiplier.latency(damageA, damageB)
  private val product = damage.asUInt(vf.width - 1 + p.powerFracBits - 1, 0)
  private val incrementWidth = vf.width - 1 + p.powerFracBits + table.shift.max
  private val damageIncrement = toUpdate(
    FixedHw.delay((product << FixedHw.delay(shift5, damageAt - 5))(incrementWidth - 1, 0), 1),
    damageAt + 1
  )
  require(
    damageAt + 1 == p.damageReadyAt(j),
    "JointMonitor: schedule differs from MonitorParams.damageReadyAt"
  )

  // ---- update stage: everything of one input cycle meets here ----
  private val valid = controlDelay(valid1, update - 1)
  private val snapshot = controlDelay(snapshot1, update - 1)
  private val clear = controlDelay(clear1, update - 1)
  private val tau = toUpdate(tau2, 2)
  private val absTau = toUpdate(absTau2, 2)
  private val absQd = toUpdate(absQd2, 2)
  private val outOfRange = toUpdate(outOfRange2, 2)
  private val aboveRepeated = toUpdate(aboveRepeated3, 3)
  private val aboveMomentary = toUpdate(aboveMomentary3, 3)
  private val bin = toUpdate(bin3, 3)

  private val cleared: JointMonitorState = {
    val c = Wire(new JointMonitorState(p, j))
    def start(f: JointField) = p.clearValue(j, f).U(p.fieldWidth(j, f).W)
    c.samples := start(JointField.Samples)
    c.outOfRangeSamples := start(JointField.OutOfRangeSamples)
    c.peakTorque := tf.minRaw.S(tf.width.W)
    c.minTorque := tf.maxRaw.S(tf.width.W)
    c.repeatedPeakSamples := start(JointField.RepeatedPeakSamples)
    c.momentaryPeakEvents := start(JointField.MomentaryPeakEvents)
    c.lastEventPeak := 0.U
    c.lastEventDuration := start(JointField.LastEventDuration)
    c.lastEventSpeed := 0.U
    c.repeatedPeakSeen := false.B
    c.momentaryPeakSeen := false.B
    c.inEvent := p.clearInEvent.B
    c.histogramSaturated := false.B
    c.damageSum := start(JointField.DamageSum)
    c.speedSum := start(JointField.SpeedSum)
    c.histogram := VecInit(Seq.fill(p.histogramBins(j))(0.U(p.histogramBitsPerJoint.W)))
    c
  }

  private val live = RegInit(cleared)
  private val shadow = RegInit(cleared)
  private val start = Mux(clear, cleared, live)
  private val next = WireDefault(start)
  // Accumulators use +%: their widths are proven for the sample budget (MonitorParams.proofLines).
  when(valid && outOfRange) {
    next.outOfRangeSamples := start.outOfRangeSamples +% 1.U
  }.elsewhen(valid) {
    val continuing = aboveMomentary && start.inEvent
    val newEventPeak = aboveMomentary && (!start.inEvent || absTau > start.lastEventPeak)
    next.samples := start.samples +% 1.U
    next.peakTorque := Mux(tau > start.peakTorque, tau, start.peakTorque)
    next.minTorque := Mux(tau < start.minTorque, tau, start.minTorque)
    next.repeatedPeakSamples := start.repeatedPeakSamples +% aboveRepeated.asUInt
    next.repeatedPeakSeen := start.repeatedPeakSeen || aboveRepeated
    next.momentaryPeakEvents := start.momentaryPeakEvents +% (aboveMomentary && !start.inEvent).asUInt
    when(newEventPeak) {
      next.lastEventPeak := absTau
      next.lastEventSpeed := absQd
    }
    next.lastEventDuration := Mux(
      continuing,
      start.lastEventDuration +% 1.U,
      Mux(aboveMomentary, 1.U, start.lastEventDuration)
    )
    next.inEvent := aboveMomentary
    next.momentaryPeakSeen := start.momentaryPeakSeen || aboveMomentary
    next.damageSum := start.damageSum +% damageIncrement
    next.speedSum := start.speedSum +% absQd
    // Saturating counters: a full counter holds its value and raises the sticky flag.
    val full = start.histogram.map(_ === p.histogramMax.U)
    next.histogram := VecInit(start.histogram.zip(full).zip(bin).map { case ((count, isFull), hit) =>
      Mux(hit && !isFull, count +% 1.U, count)
    })
    next.histogramSaturated := start.histogramSaturated || full
      .zip(bin)
      .map { case (f, b) => f && b }
      .reduce(_ || _)
  }
  live := next
  when(snapshot)(shadow := live)
  io.shadow := shadow
  io.flags.foreach(_ := live.field(JointField.Flags, JointField.FlagBit.count))
}
