"""Design: requirement specs (:mod:`.spec`, quantities with units by :mod:`.units`), the
differentiable design model of a spec (:mod:`.model`), its JSON record (:mod:`.record`) and the
design optimizer (:mod:`.optimizer`)."""
