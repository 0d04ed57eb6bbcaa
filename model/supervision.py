"""Speed supervision and brake command output (seed 000 section 2.4.3, seed 002 section 3.2).

Each cycle the measured speed is compared with the supervision limits at the
train's current position (the first element of each braking curve, seed 000
section 2.4.3): above the warning limit a warning is given, above SBI the
(full) service brake is commanded, above EBI the emergency brake. The EB command
is latched: once given it is held until the train is at standstill *and* the
release input is present (seed 000 section 2.4.3, Fig. 11). A train that cannot
determine its position is emergency braked (seed 001 section 3.2). The service brake is
held until the speed is back under the permitted speed (Subset-026 3.13.10.4
style revocation). Traction is cut off whenever a brake is commanded.

If the train has no service-brake interface the ATP commands the emergency brake
at SBI instead (Subset-026 3.13.10.3: SBI then triggers EB), so the SBI limit is
never passed without a brake command.

The limits themselves come from the dynamic speed profile (a later node); here
they are inputs, constrained only by their order (``permitted <= warning <= SBI
<= EBI``, an assumption of the properties).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Generic

from atcs.model.node import Node
from atcs.model.ops import B, N, Ops


@dataclass(frozen=True)
class SupervisionParams(Generic[N, B]):
    service_brake_fitted: B
    """Train data: the ATP can command the service brake. If not, SBI commands EB."""


@dataclass(frozen=True)
class SupervisionState(Generic[N, B]):
    eb_latched: B
    """The emergency brake was commanded in the previous cycle."""
    sb_latched: B
    """The service brake was commanded in the previous cycle."""


@dataclass(frozen=True)
class SupervisionInputs(Generic[N, B]):
    speed_mps: N
    """Measured train speed (m/s)."""
    permitted_mps: N
    """Permitted speed at the current position (m/s)."""
    warning_mps: N
    """Warning limit at the current position (m/s)."""
    sbi_mps: N
    """Service brake intervention limit at the current position (m/s)."""
    ebi_mps: N
    """Emergency brake intervention limit at the current position (m/s)."""
    standstill: B
    """Standstill detected."""
    eb_release: B
    """Driver's (or ATS's) request to release the emergency brake."""
    position_valid: B
    """The train knows its position (:mod:`atcs.model.position`); without it, EB (seed 001 §3.2)."""


@dataclass(frozen=True)
class SupervisionOutputs(Generic[N, B]):
    warning: B
    """Audible warning: the speed is above the warning limit."""
    service_brake: B
    """Full service brake command."""
    emergency_brake: B
    """Emergency brake command."""
    traction_cut: B
    """Traction cut-off command."""


def supervision_init(o: Ops, p: SupervisionParams, s: SupervisionState):
    """Power-up: the ATP starts with the emergency brake applied (the safe state)."""
    return o.and_(s.eb_latched, o.not_(s.sb_latched))


@dataclass(frozen=True)
class Exceedances(Generic[N, B]):
    """Which supervision limits the train is over this cycle (a speed over a ceiling, or the front beyond a
    braking curve's location for the measured speed: the same decision, seed 000 §2.4.3)."""

    over_permitted: B
    over_warning: B
    over_sbi: B
    over_ebi: B


def supervise(
    o: Ops, p: SupervisionParams, s: SupervisionState, over: Exceedances, standstill, eb_release, position_valid
):
    """The supervision decision from the limits exceeded: returns (next state, commands). A train that does not
    know its position is emergency braked (seed 001 §3.2)."""
    eb_released = o.and_(standstill, eb_release)
    emergency_brake = o.or_(
        over.over_ebi,
        o.not_(position_valid),
        o.and_(over.over_sbi, o.not_(p.service_brake_fitted)),
        o.and_(s.eb_latched, o.not_(eb_released)),
    )
    service_brake = o.and_(
        p.service_brake_fitted,
        o.or_(over.over_sbi, o.and_(s.sb_latched, over.over_permitted)),
    )
    traction_cut = o.or_(emergency_brake, service_brake)
    outputs = SupervisionOutputs(
        warning=over.over_warning,
        service_brake=service_brake,
        emergency_brake=emergency_brake,
        traction_cut=traction_cut,
    )
    return SupervisionState(eb_latched=emergency_brake, sb_latched=service_brake), outputs


def supervision_step(o: Ops, p: SupervisionParams, s: SupervisionState, i: SupervisionInputs):
    """One ATP cycle of speed supervision against the limits at the current position."""
    over = Exceedances(
        over_permitted=i.speed_mps > i.permitted_mps,
        over_warning=i.speed_mps > i.warning_mps,
        over_sbi=i.speed_mps > i.sbi_mps,
        over_ebi=i.speed_mps > i.ebi_mps,
    )
    return supervise(o, p, s, over, i.standstill, i.eb_release, i.position_valid)


SUPERVISION = Node(
    name="supervision",
    params=SupervisionParams,
    state=SupervisionState,
    inputs=SupervisionInputs,
    outputs=SupervisionOutputs,
    init=supervision_init,
    step=supervision_step,
    seed="000 §2.4.3, 002 §3.2",
)
