"""The proof engine: a node's transition system (:mod:`.system`), bounded model checking (:mod:`.bmc`),
k-induction with lemmas (:mod:`.induction`), the vacuity check (:mod:`.vacuity`), one property's verdict
(:mod:`.prove`) and the suite in worker processes (:mod:`.suite`). docs/design.md, "The proof engine"."""
