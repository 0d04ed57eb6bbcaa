"""Certificates: a proof's obligations as SMT-LIB 2 scripts (:mod:`.obligations`) and their check by z3 and
cvc5 (:mod:`.campaign`)."""
