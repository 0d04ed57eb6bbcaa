"""An external implementation of the supervision step, written by hand as a team would write its own code, for
``atcs vectors check --impl``: JSON lines in (one request per vector), JSON lines out (one answer each).

``--wrong-ebi`` makes it emergency brake at the EBI (``>=``) instead of above it (``>``): the deliberate fault
the boundary vectors must catch. ``--crash-after N`` makes it exit after N answers.
"""

import json
import sys


def answer(request: dict, wrong_ebi: bool) -> dict:
    p, s, i = request["params"], request["state"], request["inputs"]
    speed = i["speed_mps"]
    over_ebi = speed >= i["ebi_mps"] if wrong_ebi else speed > i["ebi_mps"]
    over_sbi = speed > i["sbi_mps"]
    released = i["standstill"] and i["eb_release"]
    eb = (
        over_ebi
        or not i["position_valid"]
        or (over_sbi and not p["service_brake_fitted"])
        or (s["eb_latched"] and not released)
    )
    sb = p["service_brake_fitted"] and (over_sbi or (s["sb_latched"] and speed > i["permitted_mps"]))
    return {
        "id": request["id"],
        "next_state": {"eb_latched": eb, "sb_latched": sb},
        "outputs": {
            "warning": speed > i["warning_mps"],
            "service_brake": sb,
            "emergency_brake": eb,
            "traction_cut": eb or sb,
        },
    }


def main() -> None:
    wrong_ebi = "--wrong-ebi" in sys.argv
    crash_after = int(sys.argv[sys.argv.index("--crash-after") + 1]) if "--crash-after" in sys.argv else None
    for n, line in enumerate(sys.stdin):
        if crash_after is not None and n >= crash_after:
            sys.exit(7)
        print(json.dumps(answer(json.loads(line), wrong_ebi)), flush=True)


if __name__ == "__main__":
    main()
