"""Mutation testing of the proofs: where the model's step functions can be mutated (:mod:`.sites`), the mutants
(:mod:`.mutants`), the campaign proving the properties about each (:mod:`.campaign`) and the registry of
equivalent mutants (:mod:`.equivalents`, ``equivalent_mutants.toml``)."""
