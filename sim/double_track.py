"""The double-track line with a turn-back at each end (seed 002 §4.2, Fig. 9), as one closed track.

A train on the up track runs from 0 to the line's length ``L``; at the far end it turns back round a loop
of ``T`` (``turn_back_m``) onto the down track, runs it back to 0 and turns back round the near loop onto
the up track. Each turn-back is a loop the train runs round front first (a balloon loop), so the two tracks
and the turn-backs are one closed track of ``2 L + 2 T`` in the direction of travel. Its coordinate
(loop metres, ``p``) is what the simulator and the step functions see:

    [0, L)            the up track,        physical x = p
    [L, L + T)        the far turn-back
    [L + T, 2L + T)   the down track,      physical x = 2L + T - p
    [2L + T, 2L + 2T) the near turn-back

Line data (speed limits, gradients, stations and their platforms) is given once, for the up track along
``x``; the down track gets its mirror (gradients change sign, a platform keeps its side: a train on either
track has an island platform on the same hand). Rows that belong to one track (trains, protection zones,
temporary restrictions) say which with ``track = "up" | "down"``.

The seed's two zones are two wayside ATPs, each the resource manager of half the line (five stations): a
zone is a stretch of ``x`` on both tracks, with the turn-back at its end.
"""

from __future__ import annotations

from bisect import bisect_right
from dataclasses import dataclass
from fractions import Fraction

TRACKS = ("up", "down")


@dataclass(frozen=True)
class DoubleTrack:
    length_m: Fraction
    """Each track's length, the line's (x from 0 to it)."""
    turn_back_m: Fraction
    """The length of each turn-back loop."""
    zone_boundaries_m: tuple[Fraction, ...] = ()
    """Where one wayside zone ends and the next begins, along x (increasing, inside the line)."""

    @property
    def loop_m(self) -> Fraction:
        return 2 * self.length_m + 2 * self.turn_back_m

    @property
    def _mirror_m(self) -> Fraction:
        return 2 * self.length_m + self.turn_back_m

    def point(self, track: str, x_m: Fraction) -> Fraction:
        """The loop coordinate of the point ``x_m`` of ``track``, in the direction of travel."""
        return x_m if track == "up" else self._mirror_m - x_m

    def interval(self, track: str, start_m: Fraction, end_m: Fraction) -> tuple[Fraction, Fraction]:
        """The loop interval of ``[start_m, end_m)`` of ``track`` (x), in the direction of travel."""
        return (start_m, end_m) if track == "up" else (self._mirror_m - end_m, self._mirror_m - start_m)

    def place(self, p_m) -> tuple[str, float]:
        """The track (``up``, ``down`` or ``turn-back``) and the physical x of the loop coordinate ``p_m``."""
        p, L, T = float(p_m) % float(self.loop_m), float(self.length_m), float(self.turn_back_m)
        if p < L:
            return "up", p
        if p < L + T:
            return "turn-back", L
        if p < 2 * L + T:
            return "down", 2 * L + T - p
        return "turn-back", 0.0

    def zone(self, p_m) -> int:
        """The wayside zone (1, 2, ...) that manages the loop coordinate ``p_m``."""
        _, x = self.place(p_m)
        return bisect_right([float(b) for b in self.zone_boundaries_m], x) + 1

    @property
    def zones(self) -> int:
        return len(self.zone_boundaries_m) + 1

    def segments(self, starts_m, values, turn_back_value, *, negate: bool = False) -> tuple[list, list]:
        """A profile given along the up track (``values[j]`` from ``starts_m[j]``) laid out round the loop: the up
        track, the far turn-back at ``turn_back_value``, the mirrored down track (values negated if ``negate``:
        a gradient), the near turn-back. Returns (starts, values) in loop coordinates."""
        L, M = self.length_m, self._mirror_m
        ends = [*starts_m[1:], L]
        down = [(M - end, -v if negate else v) for start, end, v in zip(starts_m, ends, values, strict=True)]
        pieces = [*zip(starts_m, values, strict=True), (L, turn_back_value), *reversed(down), (M, turn_back_value)]
        return [s for s, _ in pieces], [v for _, v in pieces]
