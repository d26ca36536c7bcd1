#!/usr/bin/env python3
"""A stand-in INS: publishes raw gyro samples to gyrocomp and prints what comes back.

It publishes `RawSample`s (a static gyro: constant bias plus white noise) on `gyrocomp/raw`,
notifies the event service of the same name after each one, and reads `CompSample`s from
`gyrocomp/compensated`. Every raw sample must come back exactly once with the same `seq`; the
script checks that and exits non-zero when something was lost or arrived out of order.
The raw service takes one publisher (one INS per daemon): while another client publishes, the
script says so and exits with code 3.

Needs the iceoryx2 Python wheel of the same version as the daemon:

    python3 -m pip install iceoryx2==0.10.0

Usage:

    python3 examples/python/ins_publisher.py --count 1000 --rate-hz 1000
    # private domain (as the tests use), instead of iceoryx2's default one:
    python3 examples/python/ins_publisher.py --domain-prefix gc123_ --domain-root /tmp/gc123/

The service settings (safe overflow off, subscriber buffer 2048, history 0) equal the Rust side's
(`src/ipc/services.rs`); iceoryx2 refuses to open a service whose settings differ.
"""

import argparse
import ctypes
import math
import random
import sys
import time

import iceoryx2 as iox2


class RawSample(ctypes.Structure):
    """gyrocomp::RawSample (56 bytes), see docs/design.md "Wire types"."""

    _fields_ = [
        ("seq", ctypes.c_uint64),
        ("t_ns", ctypes.c_uint64),
        ("rate_dps", ctypes.c_double * 3),
        ("temp_c", ctypes.c_double),
        ("flags", ctypes.c_uint32),
        ("_pad", ctypes.c_uint32),
    ]

    @staticmethod
    def type_name() -> str:
        """The iceoryx2 type name; must equal the Rust `#[type_name]`."""
        return "gyrocomp::RawSample"


class CompSample(ctypes.Structure):
    """gyrocomp::CompSample.v2 (104 bytes): v1 plus the drift standard deviation per axis."""

    _fields_ = [
        ("seq", ctypes.c_uint64),
        ("t_ns", ctypes.c_uint64),
        ("rate_dps", ctypes.c_double * 3),
        ("drift_dps", ctypes.c_double * 3),
        ("model_version", ctypes.c_uint64),
        ("status", ctypes.c_uint32),
        ("_pad", ctypes.c_uint32),
        ("drift_std_dps", ctypes.c_double * 3),
    ]

    @staticmethod
    def type_name() -> str:
        """The iceoryx2 type name; must equal the Rust `#[type_name]`."""
        return "gyrocomp::CompSample.v2"


assert ctypes.sizeof(RawSample) == 56 and ctypes.sizeof(CompSample) == 104


def parse_args():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--count", type=int, default=1000, help="raw samples to publish")
    p.add_argument("--rate-hz", type=float, default=1000.0, help="publish rate (0 = as fast as possible)")
    p.add_argument("--bias-dps", type=float, default=0.05, help="constant gyro bias per axis")
    p.add_argument("--noise-dps", type=float, default=0.01, help="white noise standard deviation")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--service-prefix", default="gyrocomp", help="services <prefix>/raw, <prefix>/compensated")
    p.add_argument("--buffer", type=int, default=2048, help="subscriber buffer (samples)")
    p.add_argument("--domain-prefix", help="iceoryx2 global.prefix of a private domain")
    p.add_argument("--domain-root", help="iceoryx2 global.root_path of a private domain")
    p.add_argument("--timeout-s", type=float, default=10.0, help="give up waiting for answers after this")
    p.add_argument("--wait-for-subscriber-s", type=float, default=10.0,
                   help="wait this long for the daemon's raw subscriber before publishing")
    p.add_argument("--quiet", action="store_true", help="print only the summary")
    return p.parse_args()


def make_config(args):
    if args.domain_prefix is None and args.domain_root is None:
        return iox2.config.global_config()
    config = iox2.config.default()
    if args.domain_prefix is not None:
        config.global_cfg.prefix = iox2.FileName.new(args.domain_prefix)
    if args.domain_root is not None:
        root = args.domain_root if args.domain_root.endswith("/") else args.domain_root + "/"
        config.global_cfg.root_path = iox2.Path.new(root)
    return config


def open_stream(node, name, payload, buffer):
    service = (
        node.service_builder(iox2.ServiceName.new(name))
        .publish_subscribe(payload)
        .enable_safe_overflow(False)
        .subscriber_max_buffer_size(buffer)
        .history_size(0)
        # One publisher per stream service, as the Rust side creates them: one daemon per
        # service prefix (compensated), one INS client per daemon (raw).
        .max_publishers(1)
        .open_or_create()
    )
    event = node.service_builder(iox2.ServiceName.new(name)).event().open_or_create()
    return service, event


def create_raw_publisher(node, raw_service):
    """The raw service's one publisher (lossless), or None while another client holds it. A
    client that was killed keeps its port until its dead node is cleaned: clean, then retry once."""
    def create():
        return raw_service.publisher_builder().backpressure_strategy(
            iox2.BackpressureStrategy.RetryUntilDelivered).create()
    try:
        return create()
    except iox2.PublisherCreateError:
        node.try_cleanup_dead_nodes()
    try:
        return create()
    except iox2.PublisherCreateError:
        return None


def main():
    args = parse_args()
    iox2.set_log_level_from_env_or(iox2.LogLevel.Warn)
    node = (
        iox2.NodeBuilder.new()
        .config(make_config(args))
        .signal_handling_mode(iox2.SignalHandlingMode.Disabled)
        .create(iox2.ServiceType.Ipc)
    )
    raw_service, raw_event = open_stream(node, f"{args.service_prefix}/raw", RawSample, args.buffer)
    comp_service, comp_event = open_stream(node, f"{args.service_prefix}/compensated", CompSample, args.buffer)

    # Subscribe before publishing so no answer is missed; lossless publishing (backpressure).
    subscriber = comp_service.subscriber_builder().buffer_size(args.buffer).create()
    listener = comp_event.listener_builder().create()
    publisher = create_raw_publisher(node, raw_service)
    if publisher is None:
        print(f"error: the raw service `{args.service_prefix}/raw` already has its publisher: another INS client "
              "streams to this gyrocompd (one client per service prefix; give each IMU its own daemon)",
              file=sys.stderr)
        return 3
    notifier = raw_event.notifier_builder().create()

    # A sample sent before the daemon subscribed is lost (history 0): wait for a subscriber.
    deadline = time.monotonic() + args.wait_for_subscriber_s
    while raw_service.dynamic_config.number_of_subscribers == 0:
        if time.monotonic() > deadline:
            print("error: no subscriber on the raw service (is gyrocompd running?)", file=sys.stderr)
            return 2
        time.sleep(0.01)

    rng = random.Random(args.seed)
    period = 1.0 / args.rate_hz if args.rate_hz > 0 else 0.0
    t0 = time.monotonic_ns()
    received = []

    def drain():
        while True:
            sample = subscriber.receive()
            if sample is None:
                return
            c = sample.payload().contents
            received.append((c.seq, tuple(c.rate_dps), tuple(c.drift_dps), c.model_version, c.status,
                             tuple(c.drift_std_dps)))
            if not args.quiet:
                print(f"seq {c.seq}: rate {c.rate_dps[0]:+.5f} {c.rate_dps[1]:+.5f} {c.rate_dps[2]:+.5f} dps, "
                      f"drift {c.drift_dps[0]:+.5f} ± {c.drift_std_dps[0]:.5f}, model {c.model_version}, "
                      f"status {c.status:#x}")

    def publish(seq):
        rate = [args.bias_dps + rng.gauss(0.0, args.noise_dps) for _ in range(3)]
        raw = RawSample(seq=seq, t_ns=time.monotonic_ns() - t0, temp_c=math.nan, flags=0, _pad=0)
        raw.rate_dps[:] = rate
        publisher.loan_uninit().write_payload(raw).send()
        notifier.notify()

    # Start-up handshake: iceoryx2 attaches a subscriber to a new publisher lazily (when it first
    # looks for samples) and a full buffer of a not-yet-attached subscriber is dropped, so send one
    # sample and wait for its answer before streaming (the Rust side's `ipc::prime`).
    if args.count > 0:
        publish(0)
        deadline = time.monotonic() + args.timeout_s
        while not received and time.monotonic() < deadline:
            listener.timed_wait(iox2.Duration.from_millis(10))
            drain()
        if not received:
            print("error: no answer to the first sample (is gyrocompd running?)", file=sys.stderr)
            return 2

    for seq in range(1, args.count):
        publish(seq)
        drain()
        if period > 0:
            time.sleep(period)

    deadline = time.monotonic() + args.timeout_s
    while len(received) < args.count and time.monotonic() < deadline:
        listener.timed_wait(iox2.Duration.from_millis(50))
        drain()

    seqs = [r[0] for r in received]
    in_order = seqs == list(range(len(seqs)))
    print(f"received {len(received)}/{args.count} compensated samples, in order: {in_order}")
    stds = [s for r in received for s in r[5]]
    no_nan = all(s == s and s >= 0.0 for s in stds)
    finite = sum(1 for s in stds if s != float("inf"))
    print(f"drift std: {finite}/{len(stds)} finite, none NaN or negative: {no_nan}")
    return 0 if len(received) == args.count and in_order and no_nan else 1


if __name__ == "__main__":
    sys.exit(main())
