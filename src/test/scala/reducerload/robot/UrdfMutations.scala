package reducerload.robot

import scala.util.Random
import scala.xml.{Attribute, Elem, Node, Null, Text, XML}

/** A mutated robot file: its bytes (not always UTF-8) and what was done to it, for the failure report. */
final case class MutatedUrdf(bytes: Array[Byte], tip: String, steps: Seq[String])

/**
 * Seeded mutations of a real URDF: elements and attributes dropped, duplicated, renamed or corrupted (NaN,
 * infinities, exponents beyond a double, empty, wrong counts, unicode), references re-pointed (loops, two
 * parents), joint types changed, deep nesting, huge files, truncation and invalid bytes. One to three steps
 * per file; a mutated file may still be a valid robot.
 */
object UrdfMutations {
  private val badNumbers = Seq(
    "NaN",
    "nan",
    "inf",
    "-Infinity",
    "Infinity",
    "1e400",
    "-1e400",
    "1e-400",
    "4.9e-324",
    "1.7976931348623157e308",
    "1e308",
    "-1e308",
    "",
    " ",
    "0x10",
    "1,5",
    "1 2 3 4",
    "1 2",
    "abc",
    "0",
    "-0",
    "-1",
    "1e9",
    "1e-30",
    "1f",
    "١٢٣",
    "1.5.2",
    "+",
    "e5",
    ".",
    "9" * 400,
    "1" * 5000 + "x",
    "0 0 0",
    "1e30 0 0"
  )
  private val strangeNames = Seq(
    "リンク",
    "🤖arm",
    "a\u202Eb",
    "x y",
    "e\u0301",
    "",
    " ",
    "'quoted'",
    "\"",
    "<",
    "&amp;",
    "a" * 3000,
    "tool0",
    "base_link",
    "\u0000",
    "\t",
    "link\nname"
  )
  private val jointTypes =
    Seq("fixed", "floating", "planar", "spherical", "", "REVOLUTE", "revolute", "continuous", "prismatic")

  private def elements(n: Node): Seq[Elem] = n match {
    case e: Elem => e +: e.child.flatMap(elements)
    case _       => Nil
  }

  /** `root` with `target` (found by identity) replaced by `f(target)`. */
  private def replace(root: Node, target: Elem, f: Elem => Seq[Node]): Seq[Node] = root match {
    case e: Elem if e eq target => f(e)
    case e: Elem                => Seq(e.copy(child = e.child.flatMap(replace(_, target, f))))
    case other                  => Seq(other)
  }

  private def pick[T](rng: Random, xs: Seq[T]): T = xs(rng.nextInt(xs.size))

  private def setAttribute(e: Elem, key: String, value: String): Elem =
    e.copy(attributes = e.attributes.remove(key).append(Attribute(None, key, Text(value), Null)))

  /** One structural step on the tree; None when it does not apply (the caller tries another). */
  private def step(rng: Random, root: Elem): Option[(Elem, String)] = {
    val all = elements(root)
    val inner = all.tail
    val withAttributes = all.filter(_.attributes.nonEmpty)
    def on(target: Elem, f: Elem => Seq[Node], what: String) =
      replace(root, target, f).collectFirst { case e: Elem => (e, what) }
    rng.nextInt(9) match {
      case 0 if inner.nonEmpty =>
        val t = pick(rng, inner); on(t, _ => Nil, s"drop <${t.label}>")
      case 1 if inner.nonEmpty =>
        val t = pick(rng, inner); on(t, e => Seq(e, e), s"duplicate <${t.label}>")
      case 2 if withAttributes.nonEmpty =>
        val t = pick(rng, withAttributes)
        val key = pick(rng, t.attributes.asAttrMap.keys.toSeq)
        on(t, e => Seq(e.copy(attributes = e.attributes.remove(key))), s"drop <${t.label} $key>")
      case 3 | 4 if withAttributes.nonEmpty =>
        val t = pick(rng, withAttributes)
        val key = pick(rng, t.attributes.asAttrMap.keys.toSeq)
        val old = t.attributes.asAttrMap(key)
        val value =
          if (rng.nextBoolean() || !old.contains(' ')) pick(rng, badNumbers)
          else { // one component of a vector
            val cells = old.trim.split("\\s+")
            cells.updated(rng.nextInt(cells.length), pick(rng, badNumbers)).mkString(" ")
          }
        on(t, e => Seq(setAttribute(e, key, value)), s"<${t.label} $key='${value.take(20)}'>")
      case 5 =>
        val named = all.filter(e => e.attributes.asAttrMap.keySet.exists(k => k == "name" || k == "link"))
        if (named.isEmpty) None
        else {
          val t = pick(rng, named)
          val key = if (t.attributes.asAttrMap.contains("name")) "name" else "link"
          val value =
            if (rng.nextBoolean()) pick(rng, strangeNames)
            else pick(rng, all.flatMap(_.attributes.asAttrMap.get("name"))) // another element's name
          on(t, e => Seq(setAttribute(e, key, value)), s"<${t.label} $key='${value.take(20)}'>")
        }
      case 6 =>
        val js = all.filter(_.label == "joint")
        if (js.isEmpty) None
        else {
          val t = pick(rng, js); val kind = pick(rng, jointTypes)
          on(t, e => Seq(setAttribute(e, "type", kind)), s"joint type '$kind'")
        }
      case 7 if inner.nonEmpty =>
        val t = pick(rng, inner)
        val label =
          pick(rng, Seq("lnk", "Link", "inertia", "inertial", "mass", "origin", "joint", "link", "x"))
        on(t, e => Seq(e.copy(label = label)), s"<${t.label}> renamed <$label>")
      case 8 if inner.nonEmpty => // an element moved into another
        val t = pick(rng, inner)
        val host = pick(rng, all.filterNot(_ eq t))
        val without = replace(root, t, _ => Nil).collectFirst { case e: Elem => e }.get
        elements(without).find(e => e.label == host.label && e.attributes == host.attributes).flatMap { h =>
          replace(without, h, e => Seq(e.copy(child = e.child :+ t))).collectFirst { case e: Elem =>
            (e, s"<${t.label}> moved into <${host.label}>")
          }
        }
      case _ => None
    }
  }

  /** A text-level step on the serialised file. */
  private def textStep(rng: Random, text: String, tip: String): (Array[Byte], String) = {
    val utf8 = java.nio.charset.StandardCharsets.UTF_8
    def at(marker: String): Int = {
      val positions = marker.r.findAllMatchIn(text).map(_.start).toSeq
      if (positions.isEmpty) text.indexOf("</robot>") else pick(rng, positions)
    }
    rng.nextInt(7) match {
      case 0 =>
        val depth = pick(rng, Seq(10, 1000, 100000))
        val i = at("<link ")
        (
          (text.take(i) + "<n>" * depth + "</n>" * depth + text.drop(i)).getBytes(utf8),
          s"nesting $depth deep"
        )
      case 1 =>
        val depth = pick(rng, Seq(100, 5000, 100000))
        val i = at("<inertial>")
        ((text.take(i) + "<n>" * depth + text.drop(i)).getBytes(utf8), s"$depth unclosed elements")
      case 2 => // a long chain of fixed links hanging off the tip: a huge file and a deep tree
        val count = pick(rng, Seq(1000, 30000, 200000))
        val chain = (0 until count).map { k =>
          val parent = if (k == 0) tip else s"x$k"
          s"""<link name="x${k + 1}"/><joint name="xj$k" type="fixed"><parent link="$parent"/><child link="x${k + 1}"/></joint>"""
        }
        val i = text.lastIndexOf("</robot>")
        (
          (text.take(i) + chain.mkString("\n") + text.drop(i)).getBytes(utf8),
          s"$count fixed links after the tip"
        )
      case 3 =>
        val megabytes = pick(rng, Seq(1, 20))
        val i = at("<joint ")
        (
          (text.take(i) + "<!--" + ("x" * 1023 + "\n") * (megabytes * 1024) + "-->" + text.drop(i))
            .getBytes(utf8),
          s"a $megabytes MB comment"
        )
      case 4 =>
        val cut = rng.nextInt(text.length)
        (text.take(cut).getBytes(utf8), s"truncated at $cut")
      case 5 =>
        val bytes = text.getBytes(utf8)
        val i = rng.nextInt(bytes.length)
        (bytes.updated(i, pick(rng, Seq(0xff, 0xc3, 0x00, 0x80, 0x3c)).toByte), s"byte $i replaced")
      case _ =>
        val i = at("<joint ")
        val sibling =
          s"""<link name="y"/><joint name="yj" type="fixed"><parent link="y"/><child link="y"/></joint>"""
        (
          (text.take(i) + sibling * pick(rng, Seq(1, 20000)) + text.drop(i)).getBytes(utf8),
          "self-parented links"
        )
    }
  }

  def mutate(rng: Random, original: String, tip: String): MutatedUrdf = {
    val root = XML.loadString(original)
    val steps = 1 + rng.nextInt(3)
    val (tree, done) = (0 until steps).foldLeft((root, Vector.empty[String])) { case ((t, log), _) =>
      Iterator.continually(step(rng, t)).take(20).collectFirst { case Some(r) => r } match {
        case Some((next, what)) => (next, log :+ what)
        case None               => (t, log)
      }
    }
    val text = """<?xml version="1.0"?>""" + "\n" + tree.toString
    if (rng.nextInt(4) == 0) {
      val (bytes, what) = textStep(rng, text, tip)
      MutatedUrdf(bytes, tip, done :+ what)
    } else MutatedUrdf(text.getBytes(java.nio.charset.StandardCharsets.UTF_8), tip, done)
  }
}
