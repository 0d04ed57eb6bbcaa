"""One simulated train's state between cycles (:class:`TrainRun`), its statistics, and the simulator's own
safety checks (:class:`SafetyViolation`)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from atcs.model.ats_status import AtsStatusParams, AtsStatusState
from atcs.model.authority import AuthorityParams, AuthorityState
from atcs.model.doors import DcuState, DoorParams
from atcs.model.errors import AtcsViolation
from atcs.model.plant import PlantParams
from atcs.model.prepared_curves import PreparedHorizon
from atcs.model.profile import Profile
from atcs.model.restrictions import SpeedRestrictions
from atcs.model.supervision import SupervisionState
from atcs.model.train_data import NationalData, TrainData
from atcs.sim.monitor import Monitor
from atcs.sim.reference_profile import ReferenceProfile
from atcs.sim.scenario import TrainSpec


class SafetyViolation(AtcsViolation):
    """A collision, or a train past a protection zone's start or the line's end."""

    def __init__(self, what: str, train: str, step: int, time_s: float):
        self.what, self.train, self.step, self.time_s = what, train, step, time_s
        super().__init__(f"{train}: {what} at step {step} (t = {time_s:.1f} s)")


@dataclass
class TrainStats:
    distance_m: float = 0.0
    running_s: float = 0.0
    max_speed_kmh: float = 0.0
    emergency_brakes: int = 0
    """ATP EB commands (rising edges)."""
    service_brakes: int = 0
    """ATP service-brake interventions (rising edges)."""
    min_gap_m: float = math.inf
    """The least distance from the front to the preceding train's rear."""
    station_stops: int = 0
    """Station stops completed: stopped at the stopping point, doors opened, dwell, doors closed and locked."""


@dataclass
class TrainRun:
    spec: TrainSpec
    plant: PlantParams
    """Float plant data: the bounds the proofs assume, checked every cycle."""
    position: Monitor
    authority: AuthorityState
    authority_params: AuthorityParams
    """The whole route's; each cycle the node runs on the window the train needs (:meth:`Simulation._window`)."""
    ats_status: AtsStatusState
    ats_status_params: AtsStatusParams
    supervision: SupervisionState
    front_m: float
    speed_mps: float
    brake_cycles: float
    restrictions: SpeedRestrictions
    """The train's MRSP on exact numbers, with the ATS's temporary restrictions merged in as they come and go."""
    mrsp: Profile
    """Float, from :attr:`restrictions`."""
    gradient: Profile
    train_data: TrainData
    """Float, for the curves."""
    national: NationalData
    tag_base: int = 0
    """The index (in :attr:`Simulation.tag_positions_m`) where the train's tag table starts: its position node's
    tag indices count from it. On a loop the table is one lap of tags, moved on as the train runs round."""
    last_distance_m: float = 0.0
    last_tacho_m: float = 0.0
    """What the tachometer read for the last cycle (the distance, unless a tachometer fault is active)."""
    sensor_excess_m: float = 0.0
    """The sensors' error beyond their stated bounds since the position was last set at a tag (POS-22)."""
    door_params: DoorParams | None = None
    dcu: DcuState = field(default_factory=lambda: DcuState(False, False))
    next_station: int = 0
    """The index of the next station stop (``len(stations)``: none left)."""
    doors_opened_s: float | None = None
    """When the doors opened at the current station stop."""
    dwell_done: bool = False
    """The doors have been commanded closed at the current stop."""
    reference: ReferenceProfile | None = None
    """The minimum-time profile the ATO tracks to the next station stop (``ato.reference_profile``)."""
    references: list[ReferenceProfile] = field(default_factory=list)
    """Every profile computed so far, one per stretch."""
    outbox: list = field(default_factory=list)
    """T2T reports sent and not yet delivered: (step delivered, the report's bytes)."""
    reports_sent: int = 0
    """The sequence number of the train's last T2T report."""
    last_tag: int | None = None
    """The tag the front passed in the last cycle (read in this one)."""
    detached: tuple[float, float] | None = None
    """The rear and the speed of the wagons an ``integrity_lost`` fault left behind (None: the train is whole)."""
    since_tag_m: tuple[float, float] = (0.0, 0.0)
    """The true distance from :attr:`last_tag`'s passage to the end of the last cycle, and what the tachometer
    read of it (the odometer reading the tag reader reports with the tag)."""
    report: bytes | None = None
    """The bytes of the train's report delivered this cycle (None: none delivered)."""
    replayed: bytes | None = None
    """The report a ``t2t_replay`` fault repeats: the last one delivered before it began."""
    started: bool = False
    """The driver has released the power-up emergency brake (at departure)."""
    stopped_s: float | None = None
    """When the train last came to a standstill with EB applied."""
    curve_tables: PreparedHorizon | None = None
    """Each target's EBD table for the train's current horizon (its MRSP, gradient and EoA), built when one changes
    (:mod:`atcs.model.prepared_curves`)."""
    stats: TrainStats = field(default_factory=TrainStats)
    last: dict = field(default_factory=dict)
    """This cycle's values for the trace."""
