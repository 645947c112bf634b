"""The peer of `tools/stack-test`: a stock Autoware stack around `cooperation-dds --stack`,
played by Cyclone DDS participants (`cyclonedds` from PyPI): behavior_path_planner
(lane_change_left, static_obstacle_avoidance_left) and behavior_velocity_planner (intersection,
virtual_traffic_light), each interface upstream's `rtc_interface` on upstream's endpoints
(`upstream.py`, written from the facts of upstream's code), a stand-in for default_adapi
publishing the stack's factors on the remapped topics, an operator calling the AD API, and an
operator at the node's panel in headless Chromium (`server/panel/test/stack.mjs`).

Each check prints `PASS name` or `FAIL name: why`, the design page's sequence is printed as it
ran, and the run ends with `stack peer: N passed, M failed`; the exit status is 1 if any check
failed. Every wait is bounded.

    target/cdr-venv/bin/python tools/stack_peer --domain 42 \
        --velocity-input /cooperation/input/velocity_factors \
        --steering-input /cooperation/input/steering_factors --panel http://127.0.0.1:9090/
"""

import argparse
import sys
from pathlib import Path

sys.dont_write_bytecode = True
HERE = Path(__file__).resolve().parent
sys.path[:] = [entry for entry in sys.path if Path(entry or ".").resolve() != HERE]
sys.path.insert(0, str(HERE.parent))

from ros2_peer.matching import Checks  # noqa: E402
from stack_peer.checks import Stack  # noqa: E402
from stack_peer.world import World  # noqa: E402


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--domain", type=int, required=True)
    parser.add_argument("--velocity-input", required=True,
                        help="where default_adapi's velocity factors are remapped to")
    parser.add_argument("--steering-input", required=True,
                        help="where default_adapi's steering factors are remapped to")
    parser.add_argument("--panel", help="the URL of the node's operator panel")
    args = parser.parse_args()
    checks = Checks()
    world = World(args.domain, args.velocity_input, args.steering_input)
    stack = Stack(world, args.panel)
    for name, method in Stack.ORDER:
        print(f"---- {name}", flush=True)
        if not checks.run(name, getattr(stack, method)) and method == "matched":
            break
    print(f"stack peer: {checks.passed} passed, {checks.failed} failed", flush=True)
    return 1 if checks.failed else 0


if __name__ == "__main__":
    sys.exit(main())
