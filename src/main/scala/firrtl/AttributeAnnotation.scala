package firrtl

/**
 * A Verilog attribute on a declaration, `(* description *)`: firtool's `firrtl.AttributeAnnotation`, which
 * Chisel 6 does not ship (Chisel 7 does). Annotations reach firtool as JSON named by their class, hence this
 * package. Used through [[reducerload.fixedpoint.FixedHw.kept]].
 */
case class AttributeAnnotation(target: annotations.ReferenceTarget, description: String)
    extends annotations.SingleTargetAnnotation[annotations.ReferenceTarget] {
  def duplicate(n: annotations.ReferenceTarget): AttributeAnnotation = copy(target = n)
}
