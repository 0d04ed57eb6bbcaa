"""Counterexamples: the trace file and its exact replay (:mod:`.trace`), the float replay (:mod:`.float_replay`),
the fewest-input-changes search (:mod:`.smoothing`), the near-nominal search (:mod:`.nominal`), and the waveform
(:mod:`.vcd`) and plot (:mod:`.plot`) written next to each."""
