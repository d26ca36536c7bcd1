#!/usr/bin/env python3
"""Writes ROS 2 bags (MCAP, `sensor_msgs/msg/Imu`, CDR) with the Python `mcap` and
`mcap-ros2-support` packages, independently of gyrocomp's Rust reader (tests/mcap.rs uses it).

    imu_bag.py OUT.mcap --samples IN.csv [--topic /imu ...] [--compression zstd|lz4|none]
               [--chunk-size BYTES] [--frame-id imu] [--string-topic /note] [--cut-message N]

IN.csv has the header `t_ns,wx,wy,wz`: the header stamp in ns since the epoch and the angular
velocity in rad/s. Every row becomes one Imu message on every `--topic` (default `/imu`), its
log time 1 µs after its stamp (so a reader that took the log time for the stamp is caught).
`--string-topic` adds a `std_msgs/msg/String` channel with one message, a topic that is not an
IMU. Without `--topic` and with `--string-topic`, the bag has no Imu topic at all.
`--cut-message N` (N ≥ 2) writes the payload of the N-th message (1-based) cut to 40 bytes, through the
plain MCAP writer: a well-formed bag holding one message that cannot be decoded.
"""

import argparse
import csv
import sys

from mcap.writer import CompressionType
from mcap_ros2.writer import Writer

# The concatenated ROS 2 message definition of sensor_msgs/msg/Imu, as rosbag2 stores it.
IMU_MSGDEF = """std_msgs/Header header
geometry_msgs/Quaternion orientation
float64[9] orientation_covariance
geometry_msgs/Vector3 angular_velocity
float64[9] angular_velocity_covariance
geometry_msgs/Vector3 linear_acceleration
float64[9] linear_acceleration_covariance
================================================================================
MSG: std_msgs/Header
builtin_interfaces/Time stamp
string frame_id
================================================================================
MSG: geometry_msgs/Quaternion
float64 x
float64 y
float64 z
float64 w
================================================================================
MSG: geometry_msgs/Vector3
float64 x
float64 y
float64 z
"""
STRING_MSGDEF = "string data\n"
LOG_TIME_OFFSET_NS = 1000


def imu_message(t_ns, w, frame_id="imu", orientation=(0.0, 0.0, 0.0, 1.0), accel=(0.0, 0.0, 9.81)):
    """The dict the mcap_ros2 encoder takes for one Imu message."""
    sec, nanosec = divmod(int(t_ns), 1_000_000_000)
    ox, oy, oz, ow = orientation
    return {
        "header": {"stamp": {"sec": sec, "nanosec": nanosec}, "frame_id": frame_id},
        "orientation": {"x": ox, "y": oy, "z": oz, "w": ow},
        "orientation_covariance": [0.0] * 9,
        "angular_velocity": {"x": w[0], "y": w[1], "z": w[2]},
        "angular_velocity_covariance": [1e-6 * k for k in range(9)],
        "linear_acceleration": {"x": accel[0], "y": accel[1], "z": accel[2]},
        "linear_acceleration_covariance": [0.0] * 9,
    }


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("out")
    p.add_argument("--samples", required=True)
    p.add_argument("--topic", action="append")
    p.add_argument("--compression", choices=["zstd", "lz4", "none"], default="zstd")
    p.add_argument("--chunk-size", type=int, default=1024 * 1024)
    p.add_argument("--frame-id", default="imu")
    p.add_argument("--string-topic")
    p.add_argument("--cut-message", type=int)
    a = p.parse_args()
    topics = a.topic if a.topic is not None else ([] if a.string_topic else ["/imu"])
    compression = {"zstd": CompressionType.ZSTD, "lz4": CompressionType.LZ4, "none": CompressionType.NONE}[
        a.compression
    ]
    with open(a.samples, newline="") as f:
        rows = list(csv.DictReader(f))
    with open(a.out, "wb") as out:
        w = Writer(out, chunk_size=a.chunk_size, compression=compression)
        imu = w.register_msgdef("sensor_msgs/msg/Imu", IMU_MSGDEF)
        if a.string_topic:
            s = w.register_msgdef("std_msgs/msg/String", STRING_MSGDEF)
            t0 = int(rows[0]["t_ns"]) if rows else 0
            w.write_message(a.string_topic, s, {"data": "not an IMU"}, log_time=t0)
        for seq, row in enumerate(rows):
            t_ns = int(row["t_ns"])
            msg = imu_message(t_ns, (float(row["wx"]), float(row["wy"]), float(row["wz"])), a.frame_id)
            for topic in topics:
                if a.cut_message == seq + 1:
                    data = w._encoders[imu.id](msg)[:40]
                    channel = w._channel_ids[topic]
                    log = t_ns + LOG_TIME_OFFSET_NS
                    w._writer.add_message(channel_id=channel, log_time=log, publish_time=log, sequence=seq, data=data)
                    continue
                w.write_message(topic, imu, msg, log_time=t_ns + LOG_TIME_OFFSET_NS, sequence=seq)
        w.finish()
    print(f"{a.out}: {len(rows)} Imu messages on {topics or 'no Imu topic'} ({a.compression})", file=sys.stderr)


if __name__ == "__main__":
    main()
