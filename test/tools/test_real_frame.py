#!/usr/bin/env python3
"""The system on one real frame: an overhead camera over a RoboCup Small Size League field of
2008 (780 x 580, barrel distortion, robots with a team dot and a ring of coloured quadrants).

The frame is not in the repository (its licence is not ours); give its path in the environment:

    SOCCER_VISION_REAL_FRAME=/path/to/ssl-field-2008.jpg test/tools/test_real_frame.py

Without it (or when the file is missing) every test is skipped, and says why. What we know
about the frame is in test/tools/data/real_frame_2008/ (its README.md): hand-marked robots and
ball (truth.yaml), colour samples, the robots' pattern, the field, where field calibration
starts. The test runs the built tools as a user does:

  1. calibrate_field --image: the camera's pose, k1 and k2 from the frame's field lines;
  2. calibrate_colors: a colour table from the committed samples on the frame;
  3. detect: segmentation and identification through that table and pose;

and checks the field lines drawn back against hand-measured line centres, every marked robot
(team, id, centre within 2 px, front), no robot where none is, and the ball. Outputs (pose,
table, JSON, overlay) stay in $TMPDIR/soccer_vision_real_frame/ for a look.

Tools are found in $SOCCER_VISION_TOOLS_DIR, else in lib/soccer_vision/ under
$CATKIN_DEVEL_PREFIX and every $CMAKE_PREFIX_PATH entry (a sourced workspace, or catkin's
run_tests, which runs through devel/env.sh), else in this checkout's .ws/devel.
Run directly, or with --gtest_output=xml:FILE (as scripts/test runs the gtests) for a JUnit
file in which skipped tests carry <skipped message=...>, as gtest writes them."""
import hashlib
import json
import math
import os
import pathlib
import re
import subprocess
import sys
import tempfile
import time
import unittest

try:
    import yaml
except ImportError:  # another python3 first on PATH: only /usr/bin/python3 sees Debian's modules
    if __name__ == "__main__" and sys.executable != "/usr/bin/python3" and os.path.exists("/usr/bin/python3"):
        os.execv("/usr/bin/python3", ["/usr/bin/python3", __file__] + sys.argv[1:])
    raise

REPO = pathlib.Path(__file__).resolve().parents[2]
DATA = REPO / "test" / "tools" / "data" / "real_frame_2008"
FRAME_VARIABLE = "SOCCER_VISION_REAL_FRAME"
TOOLS = ("calibrate_field", "calibrate_colors", "detect")

# What is asserted, and why these numbers (the measured values in brackets, 2026-12-03).
MAX_CENTRE_ERROR_PX = 2.0      # robot and ball centres against the hand marks (marks good to ~1 px)
MAX_FRONT_ERROR_DEG = 20.0     # heading against the black quadrant's direction read by eye (+-15)
MAX_LINE_RMS_PX = 0.8          # calibrate_field's across-line RMS (0.55 measured; it refuses > 1)
MIN_LINE_COVERAGE = 95.0       # % of the projected lines where line pixels were found (99)
MIN_PAIRED_WITHIN_3PX = 0.98   # share of paired line pixels within 3 px (0.993)
MAX_LINE_POINT_PX = 1.5        # hand-measured line centres off the drawn-back lines (max 1.2)
MAX_LINE_POINT_RMS_PX = 0.8    # the same, RMS (0.49)
ROBOT_TOP_PX = 16.0            # a robot's top (radius 90 mm) spans about 15 px in this frame
BALL_RADIUS_M = 0.0215         # detect projects a ball at its centre's height


def find_tool(name):
    candidates = []
    if os.environ.get("SOCCER_VISION_TOOLS_DIR"):
        candidates.append(pathlib.Path(os.environ["SOCCER_VISION_TOOLS_DIR"]) / name)
    prefixes = [os.environ.get("CATKIN_DEVEL_PREFIX", "")] + os.environ.get("CMAKE_PREFIX_PATH", "").split(":")
    candidates += [pathlib.Path(p) / "lib" / "soccer_vision" / name for p in prefixes if p]
    candidates.append(REPO / ".ws" / "devel" / "lib" / "soccer_vision" / name)
    for c in candidates:
        if c.is_file() and os.access(c, os.X_OK):
            return c
    raise FileNotFoundError("%s not found (looked in: %s); build the workspace or set SOCCER_VISION_TOOLS_DIR"
                            % (name, ", ".join(str(c.parent) for c in candidates)))


def run(command):
    """Runs a tool; its output, or an error with all it said."""
    result = subprocess.run([str(c) for c in command], capture_output=True, text=True, timeout=120)
    if result.returncode != 0:
        raise RuntimeError("%s exited with %d:\n%s%s" % (" ".join(map(str, command)), result.returncode,
                                                         result.stdout, result.stderr))
    return result.stdout


# ------------------------------------------------------------------ the camera, as the tools model it

class Camera:
    """camera_info (plumb_bob) and camera_pose.yaml (optical frame in `field`), projecting as
    CameraModel::project does; checked against detect's own pixels by a test below."""

    def __init__(self, camera_info_path, pose_path):
        info = yaml.safe_load(pathlib.Path(camera_info_path).read_text())
        k = info["camera_matrix"]["data"]
        self.fx, self.cx, self.fy, self.cy = k[0], k[2], k[4], k[5]
        self.d = (list(info["distortion_coefficients"]["data"]) + [0.0] * 5)[:5]
        pose = yaml.safe_load(pathlib.Path(pose_path).read_text())
        q, t = pose["rotation"], pose["translation"]
        x, y, z, w = q["x"], q["y"], q["z"], q["w"]
        n = math.sqrt(x * x + y * y + z * z + w * w)
        x, y, z, w = x / n, y / n, z / n, w / n
        self.r = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                  [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                  [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]  # optical -> field
        self.t = [t["x"], t["y"], t["z"]]

    def project(self, p):
        d = [p[i] - self.t[i] for i in range(3)]
        c = [sum(self.r[i][j] * d[i] for i in range(3)) for j in range(3)]  # R^T (p - t)
        a, b = c[0] / c[2], c[1] / c[2]
        k1, k2, p1, p2, k3 = self.d
        r2 = a * a + b * b
        radial = 1 + k1 * r2 + k2 * r2 * r2 + k3 * r2 ** 3
        xd = a * radial + 2 * p1 * a * b + p2 * (r2 + 2 * a * a)
        yd = b * radial + p1 * (r2 + 2 * b * b) + 2 * p2 * a * b
        return self.fx * xd + self.cx, self.fy * yd + self.cy


def marking_points(field, name, step=0.002):
    """Points every `step` metres along a line or arc of a field YAML, on the carpet."""
    for line in field.get("lines", []):
        if line["name"] == name:
            (x1, y1), (x2, y2) = line["p1"], line["p2"]
            n = max(2, int(math.hypot(x2 - x1, y2 - y1) / step))
            return [(x1 + (x2 - x1) * i / n, y1 + (y2 - y1) * i / n, 0.0) for i in range(n + 1)]
    for arc in field.get("arcs", []):
        if arc["name"] == name:
            a1, a2 = arc.get("a1", 0.0), arc.get("a2", 2 * math.pi)
            (cx, cy), r = arc["center"], arc["radius"]
            n = max(2, int(r * (a2 - a1) / step))
            return [(cx + r * math.cos(a1 + (a2 - a1) * i / n), cy + r * math.sin(a1 + (a2 - a1) * i / n), 0.0)
                    for i in range(n + 1)]
    raise KeyError("no marking %s in the field file" % name)


def distance_to_polyline(p, polyline):
    best = math.inf
    for (ax, ay), (bx, by) in zip(polyline, polyline[1:]):
        dx, dy = bx - ax, by - ay
        s = max(0.0, min(1.0, ((p[0] - ax) * dx + (p[1] - ay) * dy) / (dx * dx + dy * dy or 1e-12)))
        best = min(best, math.hypot(ax + s * dx - p[0], ay + s * dy - p[1]))
    return best


def pixel_distance(a, b):
    return math.hypot(a[0] - b[0], a[1] - b[1])


# ------------------------------------------------------------------ the tests

class RealFrame2008(unittest.TestCase):
    """One frame through calibrate_field, calibrate_colors and detect, against hand marks."""

    skip_reason = None

    @classmethod
    def setUpClass(cls):
        frame = os.environ.get(FRAME_VARIABLE, "")
        if not frame:
            cls.skip_reason = ("%s is not set: the real frame is not in the repository (see the docstring "
                               "of %s)" % (FRAME_VARIABLE, pathlib.Path(__file__).name))
        elif not pathlib.Path(frame).is_file():
            cls.skip_reason = "%s=%s: no such file" % (FRAME_VARIABLE, frame)
        if cls.skip_reason:
            print("SKIPPED: " + cls.skip_reason, flush=True)
            return
        cls.frame = pathlib.Path(frame)
        cls.truth = yaml.safe_load((DATA / "truth.yaml").read_text())
        cls.field = yaml.safe_load((DATA / "field_2008.yaml").read_text())
        cls.pattern = yaml.safe_load((DATA / "pattern_2008.yaml").read_text())
        digest = hashlib.sha256(cls.frame.read_bytes()).hexdigest()
        if digest != cls.truth["frame"]["sha256"]:
            raise AssertionError("%s=%s is not the frame truth.yaml was marked on (sha256 %s, expected %s)"
                                 % (FRAME_VARIABLE, frame, digest, cls.truth["frame"]["sha256"]))
        tools = {name: find_tool(name) for name in TOOLS}
        out = pathlib.Path(tempfile.gettempdir()) / "soccer_vision_real_frame"
        out.mkdir(parents=True, exist_ok=True)
        cls.out = out
        started = time.monotonic()
        # 1. The pose, k1 and k2 from the field lines, started from the clicked corners.
        cls.field_log = run([tools["calibrate_field"], "--image", cls.frame, "--field", DATA / "field_2008.yaml",
                             "--corners", ",".join(str(c) for c in cls.truth["field_corners"]),
                             "--camera-info", DATA / "camera_info_start.yaml", "--estimate-intrinsics",
                             "--fix-focal-length", "--out", out / "camera_pose.yaml",
                             "--out-camera-info", out / "camera_info.yaml"])
        # 2. The colour table from the committed samples (the tool's defaults).
        cls.colors_log = run([tools["calibrate_colors"], "--image", cls.frame, "--samples", DATA / "samples.yaml",
                              "--out", out / "table.svct", "--preview", out / "classification.png"])
        # 3. What the system sees.
        cls.detect_log = run([tools["detect"], "--image", cls.frame, "--colors", out / "table.svct",
                              "--camera-info", out / "camera_info.yaml", "--camera-pose", out / "camera_pose.yaml",
                              "--patterns", DATA / "pattern_2008.yaml", "--field", DATA / "field_2008.yaml",
                              "--json", out / "detections.json", "--overlay", out / "overlay.png"])
        cls.seconds = time.monotonic() - started
        cls.detections = json.loads((out / "detections.json").read_text())
        cls.camera = Camera(out / "camera_info.yaml", out / "camera_pose.yaml")
        print("calibrate_field:\n" + cls.field_log + "detect:\n" + cls.detect_log, flush=True)
        print("the three tools took %.2f s; outputs (overlay.png, classification.png, detections.json) in %s"
              % (cls.seconds, out), flush=True)

    def setUp(self):
        if self.skip_reason:
            self.skipTest(self.skip_reason)

    # ---- field calibration

    def test_field_line_calibration_fits_the_painted_lines(self):
        """calibrate_field's own figures: the tool refuses an RMS above 1 px; the lines of this
        frame are 2-3 px wide and JPEG-blurred, and fitted 0.55 px with 99 % of them found."""
        log = self.field_log
        rms = float(re.search(r"across-line RMS ([0-9.]+) px", log).group(1))
        paired, within = map(int, re.search(r"paired (\d+) line pixels, (\d+) within 3 px", log).groups())
        coverage = float(re.search(r"line coverage ([0-9.]+) %", log).group(1))
        print("field lines: RMS %.3f px, %d of %d paired pixels within 3 px, coverage %.0f %%"
              % (rms, within, paired, coverage))
        self.assertLessEqual(rms, MAX_LINE_RMS_PX)
        self.assertGreaterEqual(coverage, MIN_LINE_COVERAGE)
        self.assertGreaterEqual(within / paired, MIN_PAIRED_WITHIN_3PX)

    def test_field_lines_drawn_back_through_the_pose_lie_on_the_painted_ones(self):
        """Line centres measured by hand, not by the tool's line detector, against the field
        model projected through the fitted pose and intrinsics."""
        errors = []
        cache = {}
        for point in self.truth["line_points"]:
            name = point["marking"]
            if name not in cache:
                cache[name] = [self.camera.project(p) for p in marking_points(self.field, name)]
            errors.append((distance_to_polyline(point["pixel"], cache[name]), name, point["pixel"]))
        rms = math.sqrt(sum(e * e for e, _, _ in errors) / len(errors))
        worst = max(errors)
        print("line centres off the drawn-back lines: RMS %.2f px, worst %.2f px (%s at %s), %d points"
              % (rms, worst[0], worst[1], worst[2], len(errors)))
        self.assertLessEqual(rms, MAX_LINE_POINT_RMS_PX)
        for e, name, pixel in errors:
            self.assertLessEqual(e, MAX_LINE_POINT_PX, "%s at %s is %.2f px off the drawn-back line" % (name, pixel, e))

    def test_detect_pixels_are_its_field_positions_seen_through_the_pose(self):
        """Ties the two reports of detect together and checks this file's camera model (used
        above for the lines and below for the heading) against the tools' own."""
        height = self.pattern["robot_height"]
        for robot in self.detections["robots"]:
            u, v = self.camera.project((robot["x"], robot["y"], height))
            self.assertLess(pixel_distance((u, v), (robot["u"], robot["v"])), 0.05, robot)
        for ball in self.detections["balls"]:
            u, v = self.camera.project((ball["x"], ball["y"], BALL_RADIUS_M))
            self.assertLess(pixel_distance((u, v), (ball["u"], ball["v"])), 0.05, ball)

    # ---- robots

    def front_in_image_deg(self, robot):
        """The direction in the image of detect's heading, from the robot's centre."""
        height, step = self.pattern["robot_height"], 0.05
        u0, v0 = self.camera.project((robot["x"], robot["y"], height))
        u1, v1 = self.camera.project((robot["x"] + step * math.cos(robot["theta"]),
                                      robot["y"] + step * math.sin(robot["theta"]), height))
        return math.degrees(math.atan2(v1 - v0, u1 - u0))

    def test_every_marked_robot_is_found_with_its_team_id_centre_and_front(self):
        found = self.detections["robots"]
        lines, problems = [], []
        for mark in self.truth["robots"]:
            label = "%s %d at %s" % (mark["team"], mark["id"], mark["pixel"])
            near = [r for r in found if pixel_distance((r["u"], r["v"]), mark["pixel"]) <= MAX_CENTRE_ERROR_PX]
            if len(near) != 1:
                problems.append("%s: %d robots within %.0f px" % (label, len(near), MAX_CENTRE_ERROR_PX))
                continue
            robot = near[0]
            error = pixel_distance((robot["u"], robot["v"]), mark["pixel"])
            front = self.front_in_image_deg(robot)
            front_error = abs((front - mark["front_deg"] + 180) % 360 - 180)
            lines.append("  %-24s found %s %2d at (%.2f, %.2f): %.2f px off, front %.0f deg (%.0f off), "
                         "confidence %.3f" % (label, robot["team"], robot["id"], robot["u"], robot["v"], error,
                                              front, front_error, robot["confidence"]))
            if robot["team"] != mark["team"] or robot["id"] != mark["id"]:
                problems.append("%s: found as %s %d" % (label, robot["team"], robot["id"]))
            if front_error > MAX_FRONT_ERROR_DEG:
                problems.append("%s: front %.0f deg, %.0f deg off" % (label, front, front_error))
        print("robots:\n" + "\n".join(lines))
        if problems:
            self.fail("\n".join(problems) + "\nfound: %s" % found)

    def test_no_robot_where_none_is(self):
        """Every robot detect reports is a marked one (or the robot held beyond the line, which
        may or may not be found)."""
        marks = [m["pixel"] for m in self.truth["robots"]]
        held = [m["pixel"] for m in self.truth.get("held_robots", [])]
        for robot in self.detections["robots"]:
            p = (robot["u"], robot["v"])
            if any(pixel_distance(p, h) <= ROBOT_TOP_PX for h in held):
                print("the held robot was found: %s" % robot)
                continue
            self.assertTrue(any(pixel_distance(p, m) <= MAX_CENTRE_ERROR_PX for m in marks),
                            "a robot where none is marked: %s" % robot)
        print("robots reported %d, marked %d; rejected team regions by cause: %s" % (
            len(self.detections["robots"]), len(marks),
            {k: v for k, v in self.detections["rejections"].items() if v and not k.startswith("ball")}))

    # ---- the ball

    def test_the_ball_is_the_best_ball_candidate(self):
        balls = self.detections["balls"]
        self.assertTrue(balls, "no ball reported")
        mark = self.truth["ball"]["pixel"]
        error = pixel_distance((balls[0]["u"], balls[0]["v"]), mark)
        print("ball: (%.2f, %.2f), %.2f px off the mark, confidence %.3f; %d candidates"
              % (balls[0]["u"], balls[0]["v"], error, balls[0]["confidence"], len(balls)))
        self.assertLessEqual(error, MAX_CENTRE_ERROR_PX)

    def test_no_other_ball_candidate_in_play_but_the_known_ones_on_robot_tops(self):
        """detect lists every plausible orange cluster, best first: beyond the lines they are
        kept with their confidence halved (docs/identification.md: shoes and clothes stand
        there; the tracker's parked tracks sort them out), so candidates on the people and on
        the held robot beyond the left touch line are by design. In play, only the ball may be.
        KNOWN FALSE POSITIVES, not hidden: the rims of the robots' pink quadrants (blurred into
        the black ring, with lens colour fringes) have the ball's colour; parts of them are
        classified orange and listed as ball candidates. On 2026-12-03: 2 or 3, depending on the
        build (3, on blue 6, yellow 21 and yellow 5, before commit 7a7d63c; 2 after it, which
        drops clusters on identified robots' tops: on yellow 19's rim, beyond that check's
        reach, and on the held robot). Asserted: every candidate but the first is
        on the top of a marked or held robot or beyond the lines, never elsewhere."""
        balls = self.detections["balls"]
        robots = [m["pixel"] for m in self.truth["robots"] + self.truth.get("held_robots", [])]
        half_length, half_width = self.field["length"] / 2, self.field["width"] / 2
        on_robots, beyond_lines = [], []
        for ball in balls[1:]:
            p = (ball["u"], ball["v"])
            if any(pixel_distance(p, m) <= ROBOT_TOP_PX for m in robots):
                on_robots.append(ball)
            elif abs(ball["x"]) > half_length or abs(ball["y"]) > half_width:
                beyond_lines.append(ball)
            else:
                self.fail("a ball candidate in play where there is neither ball nor robot: %s" % ball)
        describe = lambda bs: ", ".join("(%.1f, %.1f) %.3f" % (b["u"], b["v"], b["confidence"]) for b in bs)  # noqa
        print("ball candidates beyond the lines (by design): %d %s" % (len(beyond_lines), describe(beyond_lines)))
        print("KNOWN FALSE POSITIVES, ball candidates on robots' tops: %d %s" % (len(on_robots), describe(on_robots)))


# ------------------------------------------------------------------ running

if __name__ == "__main__":
    sys.path.insert(0, str(REPO / "test" / "docs"))
    from test_docs import main  # noqa: E402  (the runner and JUnit output the script tests share)
    sys.exit(main(sys.argv[1:], sys.modules[__name__]))
