package reducerload.config

import reducerload.util.IntMath.ceilDiv

/** One way a memory block can be configured: `depth` words of `width` bits (simple dual port). */
final case class BlockShape(depth: Int, width: Int) {
  override def toString: String = s"${depth}x$width"
}

/**
 * A device family: what its logic cell is called, its memory block and the shapes that block takes. A memory
 * of depth x width takes the fewest blocks of one shape, width and depth rounded up to it (the counting rule
 * of tools/estimate/README.md, step 6).
 */
sealed abstract class DeviceFamily(
    val name: String,
    val logicCell: String,
    val memoryBlock: String,
    val memoryBlockBits: Int,
    val shapes: Seq[BlockShape]
) {

  /** Blocks one memory of `depth` words of `width` bits takes. */
  def blocksFor(depth: Int, width: Int): Int =
    shapes.map(s => ceilDiv(math.max(depth, 1), s.depth) * ceilDiv(math.max(width, 1), s.width)).min

  override def toString: String = name
}

object DeviceFamily {

  /** M9K: 9 kbit, 8192x1 .. 256x36 (Cyclone IV Device Handbook, vol. 1, chapter 3, "Memory Blocks"). */
  case object CycloneIVE
      extends DeviceFamily(
        "Cyclone IV E",
        "LEs",
        "M9K",
        9216,
        Seq(8192 -> 1, 4096 -> 2, 2048 -> 4, 1024 -> 9, 512 -> 18, 256 -> 36).map { case (d, w) =>
          BlockShape(d, w)
        }
      )

  /** EBR: 18 kbit, 16384x1 .. 512x36 (ECP5 and ECP5-5G Family Data Sheet, FPGA-DS-02012, "sysMEM Memory"). */
  case object ECP5
      extends DeviceFamily(
        "ECP5",
        "LUT4s",
        "EBR",
        18432,
        Seq(16384 -> 1, 8192 -> 2, 4096 -> 4, 2048 -> 9, 1024 -> 18, 512 -> 36).map { case (d, w) =>
          BlockShape(d, w)
        }
      )
}

/**
 * A target device's resources: logic cells (Cyclone IV LEs, ECP5 LUT4s), 18x18 multiplier blocks and memory
 * blocks.
 */
final case class Device(
    name: String,
    family: DeviceFamily,
    logicElements: Int,
    multiplierBlocks: Int,
    memoryBlocks: Int
) {
  override def toString: String = name
}

object Device {

  /**
   * Cyclone IV E: Cyclone IV Device Handbook, vol. 1, Table 1-1 (Intel, "Cyclone IV FPGA Device Family
   * Overview"): LEs, M9K blocks, embedded 18x18 multipliers.
   */
  private def cyclone(n: String, les: Int, multipliers: Int, m9k: Int) =
    Device(n, DeviceFamily.CycloneIVE, les, multipliers, m9k)

  /**
   * ECP5: ECP5 and ECP5-5G Family Data Sheet (Lattice FPGA-DS-02012), Table 1.1: LUTs, EBR SRAM blocks, 18x18
   * multipliers. The open flow's Fmax proxy places on these (tools/estimate/README.md).
   */
  private def ecp5(n: String, luts: Int, multipliers: Int, ebr: Int) =
    Device(n, DeviceFamily.ECP5, luts, multipliers, ebr)

  val EP4CE30: Device = cyclone("EP4CE30", 28848, 66, 66)

  /** Every device `device.name` accepts, smallest first per family. */
  val all: Seq[Device] = Seq(
    cyclone("EP4CE6", 6272, 15, 30),
    cyclone("EP4CE10", 10320, 23, 46),
    cyclone("EP4CE15", 15408, 56, 56),
    cyclone("EP4CE22", 22320, 66, 66),
    EP4CE30,
    cyclone("EP4CE40", 39600, 116, 126),
    cyclone("EP4CE55", 55856, 154, 260),
    cyclone("EP4CE75", 75408, 200, 305),
    cyclone("EP4CE115", 114480, 266, 432),
    ecp5("LFE5U-25F", 24288, 28, 56),
    ecp5("LFE5U-45F", 43848, 72, 108),
    ecp5("LFE5U-85F", 83640, 156, 208)
  )
}

/**
 * The device a design targets and how full its logic may be.
 *
 * @param part
 *   the device (`device.name`)
 * @param maxLogicFraction
 *   the share of its logic cells a design chosen by the fit may use (`device.max-logic-fraction`)
 */
final case class DeviceTarget(part: Device = Device.EP4CE30, maxLogicFraction: Double = 0.8) {
  require(
    !maxLogicFraction.isNaN && maxLogicFraction > 0 && maxLogicFraction <= 1,
    s"device.max-logic-fraction must be in (0, 1], got $maxLogicFraction"
  )

  /** Logic cells a chosen design may use. */
  def logicBudget: Int = math.floor(part.logicElements * maxLogicFraction).toInt
}
