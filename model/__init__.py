"""The ATP model: step functions (nodes), their data types, and the Ops backends.

``NODES`` is the one place where nodes are registered; tests run every node in it
under every backend.
"""

from atcs.model.ato import ATO
from atcs.model.ats_status import ATS_STATUS
from atcs.model.authority import AUTHORITY, STOPPING_POINT
from atcs.model.closed_loop import CLOSED_LOOP, DECREASE_LOOP
from atcs.model.curves import (
    ADHESION,
    CEILING_OFFSET,
    CONVERTED_CURVES,
    CURVES,
    GRADIENT_ACCELERATION,
    GUIDANCE_CURVES,
    STEPPED_CURVES,
)
from atcs.model.deceleration import DECELERATION
from atcs.model.doors import DCU, DOOR_ENABLE, DOOR_LOOP
from atcs.model.dynamic_profile import EXCEEDANCES, MOST_RESTRICTIVE, TARGETS
from atcs.model.mrsp import MRSP, PROFILE_LOOKUP
from atcs.model.node import Node
from atcs.model.plant import PLANT, PLANT_PAIR
from atcs.model.platform_packets import PACKET44_CODEC, PACKET69_CODEC
from atcs.model.platforms import PACKET_PLATFORMS
from atcs.model.position import POSITION, TACHO_CHECK
from atcs.model.position_loop import POSITION_LOOP
from atcs.model.prepared_curves import (
    PREPARED_CONVERTED_CURVES,
    PREPARED_CURVES,
    PREPARED_STEPPED_CURVES,
    TABLE_ORDER,
    TABLE_ORDER_CONVERTED,
    TABLE_ORDER_STEPPED,
)
from atcs.model.psl import MRSP_UPDATE, PROFILE_SPLICE, PSL
from atcs.model.resources import RESOURCES
from atcs.model.separation import REPORT_CHANNEL, TWO_TRAINS, TWO_TRAINS_REPORTED
from atcs.model.supervision import SUPERVISION
from atcs.model.t2t_message import T2T_CODEC, T2T_REPORT

NODES: dict[str, Node] = {
    node.name: node
    for node in (
        SUPERVISION,
        MRSP,
        PROFILE_LOOKUP,
        PSL,
        MRSP_UPDATE,
        PROFILE_SPLICE,
        DECELERATION,
        CURVES,
        PREPARED_CURVES,
        PREPARED_STEPPED_CURVES,
        PREPARED_CONVERTED_CURVES,
        TABLE_ORDER,
        TABLE_ORDER_STEPPED,
        TABLE_ORDER_CONVERTED,
        PLANT,
        PLANT_PAIR,
        CLOSED_LOOP,
        DECREASE_LOOP,
        POSITION,
        POSITION_LOOP,
        RESOURCES,
        AUTHORITY,
        ATS_STATUS,
        TWO_TRAINS,
        TWO_TRAINS_REPORTED,
        DOOR_ENABLE,
        DCU,
        DOOR_LOOP,
        CEILING_OFFSET,
        STOPPING_POINT,
        TACHO_CHECK,
        ADHESION,
        GRADIENT_ACCELERATION,
        STEPPED_CURVES,
        CONVERTED_CURVES,
        GUIDANCE_CURVES,
        MOST_RESTRICTIVE,
        EXCEEDANCES,
        TARGETS,
        ATO,
        T2T_REPORT,
        T2T_CODEC,
        PACKET69_CODEC,
        PACKET44_CODEC,
        REPORT_CHANNEL,
        PACKET_PLATFORMS,
    )
}

__all__ = ["NODES", "Node"]
