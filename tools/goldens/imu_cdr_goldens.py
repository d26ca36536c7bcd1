#!/usr/bin/env python3
"""Golden CDR bytes of sensor_msgs/msg/Imu for the Rust decoder (src/io/ros2_imu.rs tests),
serialized by the Python `mcap-ros2-support` package, an implementation independent of ours.

    python3 tools/goldens/imu_cdr_goldens.py > tests/goldens/imu_cdr.json

Little-endian messages come from the package's public encoder (`serialize_dynamic`, what its
bag writer uses); big-endian ones from its CdrWriter with the CDR_BE encapsulation (same field
walker, `_write_complex_type`). Frame ids of several lengths move the fields after the string
across alignment boundaries.
"""

import io
import json
import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "bags"))
from imu_bag import IMU_MSGDEF, imu_message  # noqa: E402
from mcap_ros2 import _dynamic  # noqa: E402
from mcap_ros2._cdr import CdrWriter, EncapsulationKind  # noqa: E402

CASES = [
    # (t_ns, angular velocity rad/s, frame_id, orientation, linear acceleration)
    (1_700_000_000_123_456_789, (0.001, -0.002, 0.5), "imu", (0.0, 0.0, 0.0, 1.0), (0.1, -0.2, 9.81)),
    (5_000_000_000, (-1.25e-5, 3.5, -7.0e-3), "", (0.1, 0.2, 0.3, 0.927), (0.0, 0.0, 0.0)),
    (999_999_999, (1e300, -0.0, 2.0**-1060), "imu_link_frame", (0.5, 0.5, 0.5, 0.5), (-9.81, 1e-9, 3.0)),
    (42, (0.0, 0.0, 0.0), "ab", (0.0, 0.0, 0.0, 1.0), (1.0, 2.0, 3.0)),
]


def main():
    encoders = _dynamic.serialize_dynamic("sensor_msgs/msg/Imu", IMU_MSGDEF)
    encode_le = encoders["sensor_msgs/msg/Imu"]
    msgdefs = {}

    def keep(name, short, msgdef):
        msgdefs[name] = msgdef
        msgdefs[short] = msgdef

    _dynamic._for_each_msgdef("sensor_msgs/msg/Imu", IMU_MSGDEF, keep)
    msgdefs.setdefault("builtin_interfaces/Time", _dynamic.TimeDefinition)
    imu_def = msgdefs["sensor_msgs/msg/Imu"]
    out = []
    for t_ns, w, frame, orientation, accel in CASES:
        msg = imu_message(t_ns, w, frame, orientation, accel)
        be = io.BytesIO()
        _dynamic._write_complex_type(imu_def.msg_name, imu_def.fields, msgdefs, msg, CdrWriter(be, EncapsulationKind.CDR_BE))
        sec, nanosec = divmod(t_ns, 1_000_000_000)
        for order, data in (("le", encode_le(msg)), ("be", be.getvalue())):
            out.append(
                {
                    "byte_order": order,
                    "hex": data.hex(),
                    "sec": sec,
                    "nanosec": nanosec,
                    "frame_id": frame,
                    "orientation": list(orientation),
                    "angular_velocity": list(w),
                    "linear_acceleration": list(accel),
                }
            )
    json.dump({"generator": "tools/goldens/imu_cdr_goldens.py (mcap-ros2-support)", "messages": out}, sys.stdout, indent=1)
    print()


if __name__ == "__main__":
    main()
