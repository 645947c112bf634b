"""The ROS 2 side of `tools/ros2-interop`, run as `python tools/ros2_peer`: see `__main__.py`.

    messages.py        the message types: tools/cdr_golden.py's, the sync service's, the
                       request/reply wrappers and the malformed requests
    dds.py             the node's names, the run's timing, the participant, readers and clients
    matching.py        comparing answers with what is expected, and recording the checks
    checks_start.py    the node as found: the graph, the topics, the policies, the first scenes
    checks_requests.py the operator's and the modules' requests: accepted, refused, malformed
    __main__.py        the run, the self-test and the arguments
"""

import sys

# No compiled files in the tree, however the package is imported.
sys.dont_write_bytecode = True
