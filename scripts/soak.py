"""The soak run of scripts/soak: the whole system on the synthetic field (demo.launch, by
default two cameras at 60 Hz, one nodelet manager) for N minutes, on a private ROS master
at 127.0.0.1. Every few seconds it samples the manager's resident memory and CPU time
(/proc) and the nodelets' /diagnostics (frames published, processed and dropped, the
tracker's latency from capture to output). At the end it prints the memory slope (least
squares after a warm-up) and fails on growth beyond the noise, on dropped frames, or when
the manager died. With --replay-frames the cameras render that many frames once and show
them forth and back: the live system at rates the renderer cannot reach (Division A's
2 x 2448x2048 at 75 Hz, docs/performance.md)."""
import argparse
import os
import re
import signal
import socket
import subprocess
import sys
import time


def free_port():
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def scenario_launch_args(scenario):
    """demo.launch's arguments for a scenario preset (name or YAML path): its pattern, field
    and measurement offset, as scripts/demo sets them."""
    if not scenario:
        return []
    import yaml

    path = scenario if scenario.endswith(".yaml") else os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "config", "scenarios", scenario + ".yaml")
    with open(path) as f:
        s = yaml.safe_load(f) or {}
    sensor = s.get("sensor") or {}
    offset = sensor.get("exposure", 0.004) / 2 if sensor.get("blur_samples", 1) > 1 else 0
    return [f"scenario:={scenario}", f"pattern:={s.get('pattern', 'two_tag')}", f"field:={s.get('field', 'div_b')}",
            f"measurement_offset:={offset:g}"]


def manager_pid(name):
    for pid in os.listdir("/proc"):
        if not pid.isdigit():
            continue
        try:
            with open(f"/proc/{pid}/cmdline", "rb") as f:
                args = f.read().split(b"\0")
        except OSError:
            continue
        if b"manager" in args and any(a == f"__name:={name}".encode() for a in args):
            return int(pid)
    return None


def rss_mb(pid):
    with open(f"/proc/{pid}/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    raise OSError("no VmRSS")


def cpu_seconds(pid):
    with open(f"/proc/{pid}/stat") as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def slope_and_noise(ts, ys):
    """Least-squares slope of ys over ts and the standard deviation of the residuals."""
    n = len(ts)
    mt, my = sum(ts) / n, sum(ys) / n
    stt = sum((t - mt) ** 2 for t in ts)
    slope = sum((t - mt) * (y - my) for t, y in zip(ts, ys)) / stt if stt > 0 else 0.0
    res = [y - (my + slope * (t - mt)) for t, y in zip(ts, ys)]
    return slope, (sum(r * r for r in res) / max(1, n - 2)) ** 0.5


class Diagnostics:
    """The latest value of every counter of the soccer_vision nodelets."""

    def __init__(self):
        import rospy
        from diagnostic_msgs.msg import DiagnosticArray

        self.values = {}
        self.latency_windows = []  # (p50, p99) [ms] of each of the tracker's diagnostics windows
        self.publish_windows = []  # (p50, p99) [ms] capture -> publish of each camera's windows
        self.udp_windows = []  # (p50, p99) [ms] capture -> tracked SSL packet sent
        rospy.Subscriber("/diagnostics", DiagnosticArray, self.callback, queue_size=50)

    def callback(self, msg):
        for st in msg.status:
            window = {}
            for kv in st.values:
                self.values[(st.name, kv.key)] = kv.value
                if kv.key in ("latency p50 [ms]", "latency p99 [ms]", "rate [Hz]"):
                    window[kv.key] = float(kv.value)
                if kv.key.startswith("capture -> ") and kv.key.endswith(" [ms]"):
                    window[kv.key] = float(kv.value)
            if {"latency p50 [ms]", "latency p99 [ms]"} <= window.keys() and window.get("rate [Hz]", 0) > 0:
                self.latency_windows.append((window["latency p50 [ms]"], window["latency p99 [ms]"]))
            for what, windows in (("publish", self.publish_windows), ("tracked packet sent", self.udp_windows)):
                p50, p99 = window.get(f"capture -> {what} p50 [ms]"), window.get(f"capture -> {what} p99 [ms]")
                if p50 is not None and p99 is not None and p50 == p50:  # NaN: no frame in the window
                    windows.append((p50, p99))

    def counters(self, key_pattern):
        """{(status name, key): value} of the integer counters whose key matches."""
        out = {}
        for (name, key), value in list(self.values.items()):
            if re.search(key_pattern, key):
                try:
                    out[(name, key)] = int(float(value))
                except ValueError:
                    pass
        return out

    def total(self, key_pattern):
        return sum(self.counters(key_pattern).values())


def main():
    parser = argparse.ArgumentParser(prog="scripts/soak", description=__doc__)
    parser.add_argument("--minutes", type=float, default=10.0, help="run time (0.5..600, default 10)")
    parser.add_argument("--interval", type=float, default=5.0, help="[s] between samples (1..60, default 5)")
    parser.add_argument("--max-slope", type=float, default=1.0,
                        help="[MB/h] memory slope allowed beyond the noise (default 1)")
    parser.add_argument("--max-growth", type=float, default=0.0,
                        help="[MB] rise over the window allowed at any slope (default 0): a short run's "
                             "allowance for the allocator's last steps of warm-up")
    parser.add_argument("--warmup", type=float, default=-1,
                        help="[s] left out of the memory slope at the start (default: a fifth of the run)")
    parser.add_argument("--max-dropped-share", type=float, default=0.0,
                        help="share of the published frames the vision system may drop (default 0)")
    parser.add_argument("--scenario", default="", help="scenario preset of demo.launch (default: the embedded one)")
    parser.add_argument("--cameras", type=int, default=2, help="cameras of the scenario (1..8, default 2)")
    parser.add_argument("--fps", type=float, default=60.0, help="[Hz] frame rate of every camera (default 60)")
    parser.add_argument("--replay-frames", type=int, default=0,
                        help="each camera renders this many frames once and shows them forth and back (default 0: "
                             "rendered live)")
    parser.add_argument("--ssl", action="store_true",
                        help="also send the SSL packets (to 127.0.0.1) and report capture -> tracked packet sent")
    parser.add_argument("--startup", type=float, default=15.0,
                        help="[s] after the first frames before counting (colour tables, first tracks; default 15)")
    parser.add_argument("--gtest_output", default="",
                        help="xml:FILE: also write the outcome as a JUnit file (as a test under catkin)")
    a = parser.parse_args()
    if not 0.5 <= a.minutes <= 600 or not 1 <= a.interval <= 60 or a.max_slope < 0 or a.max_growth < 0:
        parser.error("--minutes must be 0.5..600, --interval 1..60, --max-slope and --max-growth >= 0")
    if a.warmup > 0.8 * a.minutes * 60 or not 0 <= a.max_dropped_share <= 1:
        parser.error("--warmup must leave a fifth of the run, --max-dropped-share be 0..1")
    if not 1 <= a.cameras <= 8 or not 0 < a.fps <= 1000 or a.replay_frames < 0 or a.replay_frames == 1 \
            or not 0 <= a.startup <= 600:
        parser.error("--cameras must be 1..8, --fps 0..1000, --replay-frames 0 or >= 2, --startup 0..600")

    port = free_port()
    env = dict(os.environ, ROS_MASTER_URI=f"http://127.0.0.1:{port}", ROS_IP="127.0.0.1")
    env.pop("ROS_HOSTNAME", None)
    os.environ.update(ROS_MASTER_URI=env["ROS_MASTER_URI"], ROS_IP="127.0.0.1")
    os.environ.pop("ROS_HOSTNAME", None)
    manager = f"soak_manager_{port}"
    launch = subprocess.Popen(
        ["roslaunch", "-p", str(port), "soccer_vision", "demo.launch", f"cameras:={a.cameras}", f"fps:={a.fps:g}",
         f"replay_frames:={a.replay_frames}", f"manager:={manager}", f"table_dir:=/tmp/soccer_vision_soak_{port}"]
        + scenario_launch_args(a.scenario) + (["ssl_output:=true", "ssl_address:=127.0.0.1"] if a.ssl else []),
        env=env, stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT, start_new_session=True)
    try:
        failures = run(a, manager, launch)
        write_junit(a.gtest_output, a.minutes, failures)
        return 1 if failures else 0
    finally:
        os.killpg(launch.pid, signal.SIGINT)
        try:
            launch.wait(timeout=30)
        except subprocess.TimeoutExpired:
            os.killpg(launch.pid, signal.SIGKILL)


def write_junit(option, minutes, failures):
    if not option.startswith("xml:"):
        return
    from xml.sax.saxutils import quoteattr

    body = "".join(f"<failure message={quoteattr(f)}/>" for f in failures)
    with open(option[4:], "w") as f:
        f.write(f'<?xml version="1.0"?>\n<testsuites><testsuite name="soak" tests="1" failures="{len(failures)}" '
                f'errors="0"><testcase classname="soak" name="whole_system_{minutes:g}_minutes">{body}'
                f"</testcase></testsuite></testsuites>\n")


def run(a, manager, launch):
    """The list of failures (empty: the soak passed)."""
    import rospy

    deadline = time.time() + 60
    pid = None
    while pid is None and time.time() < deadline and launch.poll() is None:
        time.sleep(0.5)
        pid = manager_pid(manager)
    if pid is None:
        print("soak: FAILED, the nodelet manager did not start", file=sys.stderr)
        return ["the nodelet manager did not start"]
    rospy.init_node("soak_monitor", anonymous=True, disable_signals=True)
    diag = Diagnostics()
    # Start-up: colour tables, the replay's frames, first frames, the tracker's first tracks.
    deadline = time.time() + 300 + a.replay_frames * a.cameras * 0.5
    while diag.total(r"^frames processed$") == 0:
        if time.time() > deadline or launch.poll() is not None or not os.path.exists(f"/proc/{pid}"):
            print("soak: FAILED, no frame was processed", file=sys.stderr)
            return ["no frame was processed"]
        time.sleep(1)
    time.sleep(a.startup)
    start = time.time()
    start_cpu = cpu_seconds(pid)
    start_published = diag.total(r"^frames published$")
    start_processed = diag.total(r"^frames processed$")
    # Drops of the vision system (segmentation's by cause, identification's, the tracker's
    # late frames), apart from frames the synthetic source missed (rendering behind time).
    vision_drops = r"^dropped: |^frames dropped \(late"
    start_drop_counters = diag.counters(vision_drops)
    start_dropped = sum(start_drop_counters.values())
    start_missed = diag.total(r"^frames dropped by the source$")
    start_windows = len(diag.latency_windows)
    start_publish_windows = len(diag.publish_windows)
    start_udp_windows = len(diag.udp_windows)
    ts, rss = [], []
    print(f"soak: {a.minutes:g} min, {a.cameras} cameras at {a.fps:g} Hz"
          f"{f', {a.replay_frames} frames replayed' if a.replay_frames else ''}, manager pid {pid}, "
          f"sampling every {a.interval:g} s")
    while time.time() - start < a.minutes * 60:
        time.sleep(a.interval)
        if not os.path.exists(f"/proc/{pid}"):
            print("soak: FAILED, the nodelet manager died", file=sys.stderr)
            return ["the nodelet manager died"]
        ts.append((time.time() - start) / 3600.0)
        rss.append(rss_mb(pid))
    elapsed = time.time() - start
    cpu = 100.0 * (cpu_seconds(pid) - start_cpu) / elapsed
    published = diag.total(r"^frames published$") - start_published
    processed = diag.total(r"^frames processed$") - start_processed
    dropped = diag.total(vision_drops) - start_dropped
    missed = diag.total(r"^frames dropped by the source$") - start_missed
    # Warm-up (allocator pools, caches, tracks appearing): by default the first fifth.
    first = len(ts) // 5 if a.warmup < 0 else sum(1 for t in ts if t * 3600.0 < a.warmup)
    slope, noise = slope_and_noise(ts[first:], rss[first:])
    window_h = ts[-1] - ts[first]
    growth = slope * window_h
    print(f"soak: manager RSS {rss[first]:.1f} -> {rss[-1]:.1f} MB, slope {slope:+.2f} MB/h "
          f"(residual noise {noise:.2f} MB), CPU {cpu:.0f} % of one core")
    print(f"soak: frames published {published}, processed {processed}, dropped by the vision system "
          f"{dropped}; missed by the synthetic cameras (behind time) {missed} "
          f"({processed / elapsed:.1f} Hz processed over all cameras)")
    for what, all_windows, start_index in (("capture -> tracked output", diag.latency_windows, start_windows),
                                           ("capture -> image published", diag.publish_windows,
                                            start_publish_windows),
                                           ("capture -> tracked SSL packet sent", diag.udp_windows,
                                            start_udp_windows)):
        windows = sorted(all_windows[start_index:], key=lambda w: w[1])
        if windows:
            median = windows[len(windows) // 2]
            print(f"soak: latency {what} over {len(windows)} diagnostics windows: p50 {median[0]:.2f} ms, "
                  f"p99 {median[1]:.2f} ms in the median window, p99 {windows[-1][1]:.2f} ms in the worst")
    # Nothing is dropped silently: every counter that rose, with its nodelet and cause.
    for (name, key), value in sorted(diag.counters(vision_drops).items()):
        rise = value - start_drop_counters.get((name, key), 0)
        if rise:
            print(f"soak:   {rise} x {name}: {key}")
    failed = []
    # Growth beyond noise: the fitted rise over the window exceeds three residual standard
    # deviations, the allowed slope and the allowed rise.
    if slope > a.max_slope and growth > max(3 * noise, a.max_growth):
        failed.append(f"memory grows {slope:.2f} MB/h, {growth:.1f} MB over the window (> {a.max_slope:g} MB/h, "
                      f"{a.max_growth:g} MB and beyond the noise)")
    if dropped > a.max_dropped_share * published:
        failed.append(f"{dropped} frames dropped (allowed: {a.max_dropped_share:g} of {published})")
    if published == 0 or processed < 0.95 * published:
        failed.append(f"only {processed} of {published} published frames processed")
    if failed:
        print("soak: FAILED: " + "; ".join(failed), file=sys.stderr)
    else:
        print("soak: ok")
    return failed


if __name__ == "__main__":
    sys.exit(main())
