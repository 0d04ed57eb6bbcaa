"""Certified test vectors: the coverage goals (:mod:`.goals`), their generation with z3 (:mod:`.generate`), the
vector files (:mod:`.files`), their re-check against the model (:mod:`.verify`) and the run of an external
implementation over them (:mod:`.check`)."""
