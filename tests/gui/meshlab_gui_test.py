#!/usr/bin/env python3
"""The MeshLab GUI test: our filter run the way a user runs it, under Xvfb.

Starts Xvfb on a free display and a real MeshLab on a copy of a disk mesh in a work folder:
  2020.09  Debian 12's `meshlab`, from a private prefix that holds our plugin
           (scripts/make-meshlab-prefix.sh);
  2022.02  Debian 13's (trixie) and 2025.07 Debian sid's `meshlab`, each in its Debian root
  2025.07  (scripts/make-meshlab-root.sh), run with chroot in a private mount namespace (the
           root gets /proc and the X socket, the host is not touched); our plugin sits in
           MeshLab's per-user plugin folder, $HOME/.local/share/VCG/MeshLab_64bit_fp/
           MeshLabExtraPlugins/<version>/, of a fresh HOME inside the root, as a user installs it,
           or (--install system) in the root's /usr/lib/x86_64-linux-gnu/meshlab/plugins.
Then, with xdotool:
the menus by keyboard, Filters (Alt+L, the "Fi&lters" mnemonic) -> Texture -> "Parametrization:
Straightest Distances" (arrow keys, Enter); the parameter dialog opens; its Apply and Close
buttons are clicked with the mouse; MeshLab is quit with Ctrl+Q (a "Close without saving?" prompt, if one comes, is answered Yes). Xvfb and
MeshLab are always stopped, on failure too.

Checks, each on real behaviour:
  plugins  no "Error while loading plugins." window opened before the main window, nor is one
           open once the mesh is drawn;
  menu     the Texture submenu opened with two rows more than Debian's own Texture filters, the
           highlighted row is the one where our entry sorts (MeshLab sorts a category's filters
           by name), and the window that opens on Enter is titled with our filter's name
           (xdotool search --name): the entry was ours;
  dialog   that window is visible while its screenshot is taken;
  apply    MeshLab's log (the GUI echoes its log pane to stderr as "LOG: <level> <text>") has our
           report line "L2 stretch ..., flipped faces 0, ..." and "Applied filter
           Parametrization: Straightest Distances";
  texture  the checkerboard PNG was written into the work folder, next to the mesh, and holds
           exactly our three colours (light grey 235, dark grey 40, red grid (200,40,40));
  render   the 3D view shows the checkerboard after Apply and did not before: dark-grey and red
           pixel shares and light/dark alternations along rows, measured in the 3D view's region
           of screenshots taken before and after;
  quit     MeshLab exits by itself after Ctrl+Q.

Screenshots (PNG) and logs go to OUT: 01_before.png, 02_menu.png, 03_dialog.png,
04_textured.png (and failure.png when a step fails), meshlab.log, xvfb.log, result.txt and
layout.json (where the menus, the dialog and the 3D view were on screen).

With --filter atlas the same steps and checks run the atlas filter ("Parametrization:
Straightest Distances Atlas", on a closed mesh; its log line "charts N, ..., flipped_faces 0" and
its texture straightest_atlas.png). With --export NAME.obj the mesh is then saved as a user saves
it, File -> Export Mesh As with the defaults of both dialogs (05_export_file.png,
06_export_options.png), and the OBJ is checked on its own (tests/meshlab/check_obj_uv.py).
usage: meshlab_gui_test.py --plugin libfilter_straightest_param.so --mesh disk.off --out DIR
                           [--prefix DIR | --root DIR --meshlab-version 2022.02|2025.07]
                           [--filter patch|atlas] [--export NAME.obj]
Python standard library only, plus the Xvfb, xdotool, xwininfo and ImageMagick (import, convert)
command-line tools. Exit status 0 = pass, 1 = a check failed, 2 = a tool is missing.
"""

import argparse
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "meshlab_roots"))
import debian_root  # noqa: E402

FILTER_NAME = "Parametrization: Straightest Distances"  # docs/method.md section 6
# The plugin's second filter (docs/method.md section 7), in the same Texture submenu.
ATLAS_FILTER_NAME = "Parametrization: Straightest Distances Atlas"
MAIN_TITLE = r"^MeshLab 20[0-9.]+ - \["
PLUGIN_ERROR_TITLE = r"^Error while loading plugins"  # MeshLab 2022+'s QMessageBox
SYSTEM_PLUGIN_FOLDER = "/usr/lib/x86_64-linux-gnu/meshlab/plugins"  # Debian's, in a root
SCREEN = (1280, 900)
# Filters menu of MeshLab 2020.09 (src/meshlab/mainwindow_Init.cpp, fillFilterMenu): "Apply filter"
# (disabled until a filter has run, so the keyboard skips it), "Show current filter script", a
# separator, then the categories in this fixed order.
FILTER_CATEGORIES = [
    "Selection", "Cleaning and Repairing", "Create New Mesh Layer",
    "Remeshing, Simplification and Reconstruction", "Polygonal and Quad Mesh",
    "Color Creation and Processing", "Smoothing, Fairing and Deformation",
    "Quality Measure and Computations", "Normals, Curvatures and Orientation", "Mesh Layer",
    "Raster Layer", "Range Map", "Point Set", "Sampling", "Texture", "Camera",
]
# Filters -> Texture of Debian's meshlab 2020.09 package without ours. Each category lists its
# filters sorted by name (a QMap keyed by name), so our row is where our name sorts among these.
DEBIAN_2020_09_TEXTURE_FILTERS = [
    "Convert PerVertex UV into PerWedge UV",
    "Convert PerWedge UV into PerVertex UV",
    "Merge Wedge Texture Coord",
    "Parameterization + texturing from registered rasters",
    "Parameterization from registered rasters",
    "Parametrization: Flat Plane",
    "Parametrization: Trivial Per-Triangle",
    "Parametrization: Voronoi Atlas",
    "Per Vertex Texture Function",
    "Per Wedge Texture Function",
    "Project active rasters color to current mesh, filling the texture",
    "Quality from raster coverage (Face)",
    "Quality from raster coverage (Vertex)",
    "Select Vertex Texture Seams",
    "Set Texture",
    "Transfer: Texture to Vertex Color (1 or 2 meshes)",
    "Transfer: Vertex Attributes to Texture (1 or 2 meshes)",
    "Transfer: Vertex Color to Texture",
]
# The same submenu of the MeshLab 2022.02 (Debian 13) and 2025.07 (Debian sid) packages, read off
# their GUIs: 2022.02 adds libigl's Harmonic and LSCM filters and the texture defragmentation;
# sid's 2025.07 has the defragmentation but no libigl filters (libigl is not packaged there).
# Their Filters menus add an "Other" category at the end, after Camera.
TEXTURE_FILTERS = {
    "2020.09": DEBIAN_2020_09_TEXTURE_FILTERS,
    "2022.02": DEBIAN_2020_09_TEXTURE_FILTERS + [
        "Harmonic Parametrization", "Least Squares Conformal Maps Parametrization",
        "Texture Map Defragmentation"],
    "2025.07": DEBIAN_2020_09_TEXTURE_FILTERS + ["Texture Map Defragmentation"],
}
# "Applied filter NAME in N msec"; 2025.07 writes "Applied filter: NAME".
APPLIED_LINE = r"Applied filter:? %s in \d+ msec"
# io/checkerboard.cpp: light squares, dark squares, grid lines.
CHECKER_COLOURS = {(235, 235, 235), (40, 40, 40), (200, 40, 40)}
TEXTURE_NAME = "straightest_checker.png"  # default of the `texturename` parameter
ATLAS_TEXTURE_NAME = "straightest_atlas.png"  # the atlas filter's default

STEP_TIMEOUT = 60.0   # seconds for any one wait (window, render, log line)
TOTAL_TIMEOUT = 240.0  # the whole run, below the ctest TIMEOUT so that cleanup always runs


class CheckFailed(Exception):
    pass


class Gui:
    """Xvfb + MeshLab + the xdotool/ImageMagick calls the test makes."""

    def __init__(self, out, total_timeout=TOTAL_TIMEOUT):
        self.out = out
        self.xvfb = None
        self.meshlab = None
        self.env = None
        self.deadline = time.monotonic() + total_timeout
        self.started = time.monotonic()
        self.root_folder = None  # the run's folder inside a Debian root, removed at the end
        self.system_plugin = None  # our plugin in a root's system plugin folder, removed too

    # --- processes ------------------------------------------------------------------------
    def start_xvfb(self):
        read_fd, write_fd = os.pipe()
        log = open(os.path.join(self.out, "xvfb.log"), "wb")
        # -displayfd: Xvfb picks a free display number itself and writes it once it accepts
        # connections (no guessing, no race with other Xvfb on the machine).
        self.xvfb = subprocess.Popen(
            ["Xvfb", "-displayfd", str(write_fd), "-screen", "0", "%dx%dx24" % SCREEN,
             "-nolisten", "tcp", "-noreset"],
            pass_fds=(write_fd,), stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
        os.close(write_fd)
        number = b""
        end = time.monotonic() + 30
        while time.monotonic() < end and not number.endswith(b"\n"):
            chunk = os.read(read_fd, 16)  # blocks until Xvfb writes or exits
            if not chunk:
                break
            number += chunk
        os.close(read_fd)
        if not number.strip().isdigit():
            raise CheckFailed("Xvfb did not start (see xvfb.log)")
        self.env = dict(os.environ, DISPLAY=":" + number.strip().decode())
        log_line("Xvfb on display %s" % self.env["DISPLAY"])

    def start_meshlab(self, prefix, mesh, workdir):
        # Fresh settings: MeshLab keeps its layout and the last used filter parameters in
        # $XDG_CONFIG_HOME/VCG; the test must not depend on (or change) the user's.
        for name in ("config", "data", "cache", "runtime"):
            os.makedirs(os.path.join(self.out, "xdg", name), mode=0o700, exist_ok=True)
        self.env.update(XDG_CONFIG_HOME=os.path.join(self.out, "xdg", "config"),
                        XDG_DATA_HOME=os.path.join(self.out, "xdg", "data"),
                        XDG_CACHE_HOME=os.path.join(self.out, "xdg", "cache"),
                        XDG_RUNTIME_DIR=os.path.join(self.out, "xdg", "runtime"))
        self.popen_meshlab(["nice", "-n", "5", os.path.join(prefix, "bin", "meshlab"), mesh],
                           cwd=workdir)

    def start_meshlab_in_root(self, root, home, mesh):
        """MeshLab of a Debian root (tests/meshlab_roots/debian_root.py); home and mesh are
        paths inside the root."""
        runtime = os.path.join(home, "runtime")
        os.makedirs(root + runtime, mode=0o700, exist_ok=True)
        os.chmod(root + runtime, 0o700)
        env = {"DISPLAY": self.env["DISPLAY"], "HOME": home, "XDG_RUNTIME_DIR": runtime}
        self.popen_meshlab(debian_root.command(root, ["nice", "-n", "5", "meshlab", mesh],
                                               env=env, x11=True), cwd="/")

    def popen_meshlab(self, command, cwd):
        self.meshlab_log_path = os.path.join(self.out, "meshlab.log")
        log = open(self.meshlab_log_path, "wb")
        self.meshlab = subprocess.Popen(command, cwd=cwd, env=self.env, stdout=log,
                                        stderr=subprocess.STDOUT, start_new_session=True)

    def stop(self):
        for name, proc in (("meshlab", self.meshlab), ("Xvfb", self.xvfb)):
            if proc is None or proc.poll() is not None:
                continue
            log_line("stopping %s (pid %d)" % (name, proc.pid))
            try:
                os.killpg(proc.pid, signal.SIGTERM)
                proc.wait(timeout=10)
            except (ProcessLookupError, subprocess.TimeoutExpired):
                try:
                    os.killpg(proc.pid, signal.SIGKILL)
                    proc.wait(timeout=10)
                except (ProcessLookupError, subprocess.TimeoutExpired):
                    pass

    # --- helpers --------------------------------------------------------------------------
    def remaining(self, limit=STEP_TIMEOUT):
        left = self.deadline - time.monotonic()
        if left <= 0:
            raise CheckFailed("the run took longer than %d s" % TOTAL_TIMEOUT)
        return min(limit, left)

    def run(self, *cmd, timeout=30, check=True):
        result = subprocess.run(list(cmd), env=self.env, capture_output=True, text=True,
                                timeout=self.remaining(timeout))
        if check and result.returncode != 0:
            raise CheckFailed("%s failed: %s" % (" ".join(cmd), result.stderr.strip()))
        return result.stdout

    def meshlab_alive(self):
        return self.meshlab is not None and self.meshlab.poll() is None

    def wait_for(self, what, probe, timeout=STEP_TIMEOUT, interval=0.2):
        """Polls probe() until it returns something true; returns it."""
        end = time.monotonic() + self.remaining(timeout)
        while True:
            value = probe()
            if value:
                return value
            if self.meshlab is not None and not self.meshlab_alive():
                raise CheckFailed("MeshLab exited (status %s) while waiting for %s"
                                  % (self.meshlab.returncode, what))
            if time.monotonic() > end:
                raise CheckFailed("timed out after %.0f s waiting for %s" % (timeout, what))
            time.sleep(interval)

    def windows(self, name):
        """Visible windows whose title matches the regular expression name."""
        out = self.run("xdotool", "search", "--onlyvisible", "--name", name, check=False)
        return [int(w) for w in out.split()]

    def wait_window(self, name, timeout=STEP_TIMEOUT):
        # xdotool's own --sync wait, bounded, then the same search again for the id list.
        try:
            self.run("xdotool", "search", "--sync", "--onlyvisible", "--name", name,
                     timeout=timeout, check=False)
        except subprocess.TimeoutExpired:
            pass
        return self.wait_for("a window named /%s/" % name, lambda: self.windows(name), timeout=5)

    def popups(self):
        """Visible top-level windows of MeshLab other than its main window: open menus."""
        out = self.run("xdotool", "search", "--onlyvisible", "--maxdepth", "1",
                       "--classname", "meshlab", check=False)
        result = []
        for w in (int(x) for x in out.split()):
            if w != self.main:
                result.append((w, self.geometry(w)))
        return result

    def geometry(self, window):
        out = self.run("xdotool", "getwindowgeometry", "--shell", str(window))
        g = dict(line.split("=", 1) for line in out.split())
        return int(g["X"]), int(g["Y"]), int(g["WIDTH"]), int(g["HEIGHT"])

    def focus(self, window):
        try:
            self.run("xdotool", "windowfocus", "--sync", str(window), timeout=10, check=False)
        except subprocess.TimeoutExpired:
            pass

    def key(self, *keys):
        self.run("xdotool", "key", "--delay", "80", *keys)

    def click(self, window, x, y):
        self.run("xdotool", "mousemove", "--window", str(window), str(x), str(y),
                 "click", "1")

    def park_mouse(self):
        # Over the status bar: no hover highlight or tooltip in the 3D view or on a menu.
        self.run("xdotool", "mousemove", "5", str(SCREEN[1] - 5))

    def screenshot(self, name):
        path = os.path.join(self.out, name)
        self.run("import", "-window", "root", path)
        return path

    def log_text(self):
        with open(self.meshlab_log_path, "rb") as f:
            return f.read().decode("utf-8", "replace")


# --- pixels -------------------------------------------------------------------------------
def read_region(path, box):
    """RGB bytes of box (x, y, w, h) of an image, via ImageMagick -> binary PPM."""
    x, y, w, h = box
    data = subprocess.run(["convert", path, "-crop", "%dx%d+%d+%d" % (w, h, x, y), "+repage",
                           "-depth", "8", "ppm:-"], capture_output=True, check=True).stdout
    fields, i = [], 0
    while len(fields) < 4:  # P6 width height maxval, whitespace separated, '#' comments
        while data[i:i + 1].isspace():
            i += 1
        if data[i:i + 1] == b"#":
            i = data.index(b"\n", i) + 1
            continue
        j = i
        while not data[j:j + 1].isspace():
            j += 1
        fields.append(data[i:j])
        i = j
    width, height = int(fields[1]), int(fields[2])
    return width, height, data[i + 1:i + 1 + width * height * 3]


def render_stats(path, box):
    """Checkerboard evidence in the 3D view: shares of dark-grey, light-grey and red pixels and
    the number of light<->dark alternations along rows (runs of at least 3 pixels).
    Dark grey: grey (channel spread <= 12) with 25 <= max <= 80, which excludes the background
    gradient's near-black top. Our texture under MeshLab's lighting gives dark squares ~30-45,
    light squares ~170-235 and grid lines that stay clearly red."""
    width, height, px = read_region(path, box)
    dark = light = red = alternations = 0
    for row in range(height):
        base = row * width * 3
        run_class, run_length, last_class = None, 0, None
        for col in range(width):
            r, g, b = px[base + 3 * col], px[base + 3 * col + 1], px[base + 3 * col + 2]
            hi, lo = max(r, g, b), min(r, g, b)
            cls = None
            if hi - lo <= 12 and 25 <= hi <= 80:
                dark += 1
                cls = "D"
            elif hi - lo <= 12 and lo >= 150:
                light += 1
                cls = "L"
            elif r >= 110 and r - g >= 60 and r - b >= 60:
                red += 1
            if cls == run_class:
                run_length += 1
            else:
                run_class, run_length = cls, 1
            if run_length == 3 and cls is not None:
                if last_class is not None and last_class != cls:
                    alternations += 1
                last_class = cls
    n = float(width * height)
    return {"dark": dark / n, "light": light / n, "red": red / n, "alternations": alternations}


MIN_RED = 0.001  # --min-red


def shows_checkerboard(s):
    # Red: the grid lines are one texel wide, thinner than a screen pixel at this zoom, so the
    # share that stays red follows the texel density (the torus's 6-chart atlas: 0.16 %; a
    # 1.36M-face scan's atlas at 2048: 0.03 %); before Apply only the trackball's red axis shows
    # (2025.07: 0.04 %).
    return (s["dark"] >= 0.03 and s["light"] >= 0.03 and s["red"] >= MIN_RED
            and s["alternations"] >= 800)


def fmt(s):
    return "dark %.2f%%, light %.2f%%, red %.3f%%, alternations %d" % (
        100 * s["dark"], 100 * s["light"], 100 * s["red"], s["alternations"])


def highlighted_row(path, box):
    """(top, height) of the band of rows in box that are mostly the menu highlight (blue)."""
    width, height, px = read_region(path, box)
    rows = []
    for row in range(height):
        base = row * width * 3
        blue = sum(1 for col in range(width)
                   if px[base + 3 * col + 2] >= 150
                   and px[base + 3 * col + 2] - px[base + 3 * col] >= 60)
        if blue > width // 2:
            rows.append(row)
    if not rows:
        return None
    return rows[0], rows[-1] - rows[0] + 1


def unique_colours(path):
    out = subprocess.run(["convert", path, "-depth", "8", "-unique-colors", "txt:-"],
                         capture_output=True, text=True, check=True).stdout
    colours = set()
    for m in re.finditer(r"\(\s*(\d+),\s*(\d+),\s*(\d+)", out):
        colours.add(tuple(int(v) for v in m.groups()))
    return colours


# --- the test -------------------------------------------------------------------------------
RESULTS = []
# Where things were on screen, [x, y, w, h] each, written to OUT/layout.json for
# scripts/update-readme-pictures.sh (it crops the screenshots with them).
LAYOUT = {"screen": [0, 0, SCREEN[0], SCREEN[1]]}


def log_line(text):
    print(text, flush=True)


def passed(name, detail):
    RESULTS.append("PASS %-8s %s" % (name, detail))
    log_line("PASS %-8s %s" % (name, detail))


def texture_name(args):
    return ATLAS_TEXTURE_NAME if args.filter == "atlas" else TEXTURE_NAME


def run_test(args, gui):
    target = ATLAS_FILTER_NAME if args.filter == "atlas" else FILTER_NAME
    out = args.out
    if args.root:
        # Everything MeshLab reads or writes lives in the root, under one folder per run.
        inside = "/tmp/sdp-gui-test-%s-%d" % (args.meshlab_version, os.getpid())
        gui.root_folder = args.root + inside
        home = inside + "/home"
        # The roots are the project's own cache: a copy of ours in the system folder can only be
        # left by a run of this test that was killed.
        stale = os.path.join(args.root + SYSTEM_PLUGIN_FOLDER, os.path.basename(args.plugin))
        if os.path.exists(stale):
            os.remove(stale)
        if args.install == "system":
            plugins = args.root + SYSTEM_PLUGIN_FOLDER
            gui.system_plugin = os.path.join(plugins, os.path.basename(args.plugin))
        else:
            plugins = (args.root + home + "/.local/share/VCG/MeshLab_64bit_fp/MeshLabExtraPlugins/"
                       + args.meshlab_version)
            os.makedirs(plugins)
        os.makedirs(args.root + home, exist_ok=True)
        shutil.copyfile(args.plugin, os.path.join(plugins, os.path.basename(args.plugin)))
        log_line("plugin installed in %s" % plugins[len(args.root):])
        workdir = args.root + inside + "/work"
    else:
        workdir = os.path.join(out, "work")
    os.makedirs(workdir)
    # The filter writes its texture next to the mesh: work on a copy, never in the shared folder.
    mesh = os.path.join(workdir, os.path.basename(args.mesh))
    shutil.copyfile(args.mesh, mesh)

    if not args.root:
        here = os.path.dirname(os.path.abspath(__file__))
        make_prefix = os.path.join(here, "..", "..", "scripts", "make-meshlab-prefix.sh")
        subprocess.run(["bash", make_prefix, args.prefix, args.plugin], check=True,
                       stdout=subprocess.DEVNULL)

    gui.start_xvfb()
    if args.root:
        gui.start_meshlab_in_root(args.root, home, mesh[len(args.root):])
    else:
        gui.start_meshlab(args.prefix, mesh, workdir)

    # --- main window, full screen (there is no window manager: resize it ourselves) --------
    # MeshLab 2022+ reports a plugin it refused (other version or precision, a missing library)
    # in a modal "Error while loading plugins." box, before its main window shows; 2020.09 only
    # prints it.
    def main_window_or_refusal():
        if gui.windows(PLUGIN_ERROR_TITLE):
            return "refused"
        found = gui.windows(MAIN_TITLE)
        return found[0] if found else None
    gui.main = gui.wait_for("the main window", main_window_or_refusal)
    if gui.main == "refused":
        time.sleep(1)  # let the box paint its text
        gui.screenshot("01_plugin_error.png")
        raise CheckFailed("MeshLab opened 'Error while loading plugins' (see 01_plugin_error.png)")
    # MeshLab may still restore its saved geometry or lay itself out after it shows (a CI run of
    # 2025.07 kept a smaller window for 60 s after one resize): ask again every 2 s, and take the
    # main window anew each time in case the first one found was replaced.
    def fill_screen():
        found = gui.windows(MAIN_TITLE)
        if found:
            gui.main = found[0]
        if gui.geometry(gui.main)[2:] == SCREEN:
            return True
        now = time.monotonic()
        if now - fill_screen.asked >= 2.0:
            fill_screen.asked = now
            gui.run("xdotool", "windowmove", str(gui.main), "0", "0", check=False)
            gui.run("xdotool", "windowsize", str(gui.main), str(SCREEN[0]), str(SCREEN[1]),
                    check=False)
        return False
    fill_screen.asked = -1e9
    gui.wait_for("the main window to fill the screen", fill_screen)
    log_line("MeshLab window %d after %.1f s" % (gui.main, time.monotonic() - gui.started))

    # The 3D view: the largest child of the main window (the MDI area with the GL widget); its
    # lower part holds MeshLab's info overlay (FOV, FPS, mesh name), which is left out.
    # MeshLab lays its panels out again after the resize (2025.07 under load took a while): the
    # box counts once it is the same on two polls and starts at the left, where the view is.
    def settled_view():
        box = largest_child(gui, gui.main)
        previous, settled_view.previous = settled_view.previous, box
        return box if box and box == previous and box[0] < SCREEN[0] // 4 else None
    settled_view.previous = None
    view = gui.wait_for("the 3D view", settled_view, interval=0.5)
    x, y, w, h = view
    render_box = (x, y, w, int(h * 0.85))
    LAYOUT["view"] = list(view)

    gui.park_mouse()
    before_path = os.path.join(out, "01_before.png")

    def rendered_mesh():
        # The untextured mesh is drawn light grey: wait until it is there and stable.
        gui.screenshot("01_before.png")
        s = render_stats(before_path, render_box)
        if s["light"] < 0.03:
            return None
        previous, rendered_mesh.previous = rendered_mesh.previous, s
        return s if previous == s else None
    rendered_mesh.previous = None
    before = gui.wait_for("the mesh to be drawn", rendered_mesh)
    if shows_checkerboard(before):
        raise CheckFailed("the 3D view shows a checkerboard before the filter ran: " + fmt(before))
    passed("before", "3D view without checkerboard: " + fmt(before))
    refused = gui.windows(PLUGIN_ERROR_TITLE)
    if refused:
        gui.screenshot("01_plugin_error.png")
        raise CheckFailed("MeshLab opened 'Error while loading plugins' (see 01_plugin_error.png)")
    passed("plugins", "no 'Error while loading plugins' window")

    # --- Filters -> Texture -> our entry, by keyboard ------------------------------------------
    gui.focus(gui.main)
    gui.key("alt+l")  # "Fi&lters"
    filters_menu = gui.wait_for("the Filters menu", lambda: gui.popups())
    # The first enabled entry ("Show current filter script") is highlighted on opening.
    gui.key(*(["Down"] * (FILTER_CATEGORIES.index("Texture") + 1)), "Right")
    texture_menu = gui.wait_for("the Texture submenu", lambda: [
        p for p in gui.popups() if p[0] not in {w for w, _ in filters_menu}])
    _, (mx, my, mw, mh) = texture_menu[0]
    # QString order = code units; the atlas sorts right after the patch filter.
    names = sorted(TEXTURE_FILTERS[args.meshlab_version] + [FILTER_NAME, ATLAS_FILTER_NAME])
    index = names.index(target)
    if index:
        gui.key(*(["Down"] * index))
    menu_path = os.path.join(out, "02_menu.png")

    def highlight_on_our_row():
        gui.screenshot("02_menu.png")
        band = highlighted_row(menu_path, (mx, my, mw, mh))
        if band is None:
            return None
        top, height = band
        return band if height >= 10 and round(top / float(height)) == index else None
    try:
        top, height = gui.wait_for("the highlight on row %d of the Texture submenu" % index,
                                   highlight_on_our_row, timeout=15)
    except CheckFailed:
        band = highlighted_row(menu_path, (mx, my, mw, mh))
        raise CheckFailed("Texture submenu at %s: highlighted band %s, expected row %d "
                          "(see 02_menu.png)" % ((mx, my, mw, mh), band, index))
    # All rows are as high as the highlight: the submenu holds Debian's entries plus exactly our
    # two. Without our plugin it is two rows shorter (and Enter would open another filter).
    rows = int(round(mh / float(height)))
    if rows != len(names):
        raise CheckFailed("the Texture submenu has %d rows (%d px / %d px), expected %d: Debian's "
                          "%d and our two (see 02_menu.png)" % (rows, mh, height, len(names),
                                                                 len(names) - 2))
    LAYOUT["menus"] = [list(g) for _, g in filters_menu + texture_menu]
    passed("menu", "Texture submenu %dx%d+%d+%d open with %d rows, row %d highlighted (y %d..%d)"
           " = where '%s' sorts" % (mw, mh, mx, my, rows, index, my + top,
                                    my + top + height - 1, target))

    # --- the parameter dialog ---------------------------------------------------------------
    gui.key("Return")
    dialog_title = "^%s$" % re.escape(target)
    try:
        dialog = gui.wait_window(dialog_title, timeout=30)[0]
    except CheckFailed:
        others = gui.run("xdotool", "search", "--onlyvisible", "--name", ".", "getwindowname",
                         "%@", check=False)
        raise CheckFailed("no window titled '%s' after Enter on the entry; visible windows: %s"
                          % (target, sorted(set(others.split("\n")) - {""})))
    dx, dy, dw, dh = gui.wait_for("the dialog to have its size", lambda: (
        gui.geometry(dialog) if gui.geometry(dialog)[3] > 100 else None))
    gui.park_mouse()
    time.sleep(0.5)  # let the dialog finish painting (its widgets are laid out after mapping)
    gui.screenshot("03_dialog.png")
    if not gui.windows(dialog_title):
        raise CheckFailed("the dialog vanished before its screenshot")
    LAYOUT["dialog"] = [dx, dy, dw, dh]
    passed("dialog", "window %d titled '%s', %dx%d+%d+%d" % (dialog, target, dw, dh, dx, dy))

    # --- Apply, then Close ------------------------------------------------------------------
    # MeshlabStdDialog's last row is [Close][Apply], each half the width, ~26 px high at the
    # bottom edge: the centres of the two halves, 23 px above the bottom.
    log_before = gui.log_text()
    gui.click(dialog, dw * 3 // 4, dh - 23)
    applied = APPLIED_LINE % re.escape(target)
    is_applied = lambda: re.search(applied, gui.log_text()[len(log_before):])
    if args.watch_progress:
        watch_progress(gui, is_applied, args.apply_timeout)
    gui.wait_for("'%s' in MeshLab's log" % applied, is_applied, timeout=args.apply_timeout)
    # The patch filter's line "L2 stretch ..., flipped faces 0, ...", the atlas's
    # "charts N, ..., flipped_faces 0, ..." (the report table's keys).
    marker, clean = (("charts ", "flipped_faces 0") if args.filter == "atlas" else
                     ("L2 stretch", "flipped faces 0"))
    report = [l for l in gui.log_text()[len(log_before):].splitlines() if marker in l]
    if not report or clean not in report[0]:
        raise CheckFailed("no '%s ... %s' report line in meshlab.log" % (marker, clean))
    passed("apply", "log: " + report[0].strip())

    texture = os.path.join(workdir, texture_name(args))
    if not os.path.isfile(texture):
        raise CheckFailed("%s was not written next to the mesh" % texture)
    with open(texture, "rb") as f:
        if f.read(8) != b"\x89PNG\r\n\x1a\n":
            raise CheckFailed("%s is not a PNG" % texture)
    colours = unique_colours(texture)
    if colours != CHECKER_COLOURS:
        raise CheckFailed("%s has colours %s, expected %s" % (texture, sorted(colours),
                                                                sorted(CHECKER_COLOURS)))
    passed("texture", "%s: PNG with exactly the 3 checkerboard colours" % texture)

    gui.click(dialog, dw // 4, dh - 23)
    gui.wait_for("the dialog to close", lambda: not gui.windows(dialog_title))

    # --- the textured mesh ------------------------------------------------------------------
    gui.park_mouse()
    textured_path = os.path.join(out, "04_textured.png")

    def textured():
        gui.screenshot("04_textured.png")
        s = render_stats(textured_path, render_box)
        return s if shows_checkerboard(s) else None
    try:
        after = gui.wait_for("the checkerboard in the 3D view", textured, timeout=30)
    except CheckFailed:
        raise CheckFailed("no checkerboard in the 3D view after Apply: %s (before: %s)"
                          % (fmt(render_stats(textured_path, render_box)), fmt(before)))
    # Red by its rise, not a ratio: the trackball's axis is red before Apply, and the grid
    # lines' share follows the packing's texel density.
    if not (after["dark"] >= 4 * before["dark"] and after["red"] >= before["red"] + MIN_RED
            and after["alternations"] >= 4 * before["alternations"]):
        raise CheckFailed("the 3D view changed too little: after %s, before %s"
                          % (fmt(after), fmt(before)))
    passed("render", "checkerboard: %s (before: %s)" % (fmt(after), fmt(before)))

    if args.export:
        export_mesh(args, gui, workdir)

    # --- quit -------------------------------------------------------------------------------
    gui.focus(gui.main)
    gui.key("ctrl+q")
    end = time.monotonic() + gui.remaining(30)
    answered = False
    while gui.meshlab_alive():
        if time.monotonic() > end:
            raise CheckFailed("MeshLab did not quit after Ctrl+Q")
        prompt = gui.windows("^MeshLab$")  # QMessageBox "Close without saving?"
        if prompt and not answered:
            gui.screenshot("05_quit_prompt.png")
            gui.focus(prompt[0])
            gui.key("y")  # the &Yes button
            answered = True
        time.sleep(0.2)
    passed("quit", "MeshLab exited with status %d after Ctrl+Q%s"
           % (gui.meshlab.returncode, " and Yes to the save prompt" if answered else ""))


def watch_progress(gui, is_applied, timeout):
    """While the filter runs, the main window's status bar (its bottom 24 px, where MeshLab
    shows its progress bar) is read about twice a second; each time its pixels change is a move
    the user sees. Writes progress.txt (seconds since Apply, changed or not) and a screenshot
    of the whole screen at the first change after each 10 s (progress_NN.png); passes with the
    longest wait between changes."""
    x, y, w, h = gui.geometry(gui.main)
    box = (x, y + h - 24, w, 24)
    started = time.monotonic()
    end = started + timeout
    samples, last, shots = [], None, 0
    while not is_applied():
        if time.monotonic() > end:
            raise CheckFailed("the filter did not finish within %d s" % timeout)
        now = time.monotonic() - started
        path = gui.screenshot("progress_frame.png")
        pixels = read_region(path, box)
        changed = pixels != last
        last = pixels
        samples.append((now, changed))
        if changed and now >= 10 * shots:
            shots += 1
            shutil.copyfile(path, os.path.join(gui.out, "progress_%02d.png" % shots))
        time.sleep(0.3)
    total = time.monotonic() - started
    with open(os.path.join(gui.out, "progress.txt"), "w") as f:
        f.writelines("%.2f %d\n" % (t, c) for t, c in samples)
    changes = [t for t, c in samples if c] + [total]
    longest = max((b - a for a, b in zip(changes, changes[1:])), default=total)
    passed("progress", "the status bar changed %d times in %.1f s of the filter's run (%d reads); "
           "the longest wait between changes %.1f s" % (len(changes) - 1, total, len(samples),
                                                         longest))


def export_mesh(args, gui, workdir):
    """File -> Export Mesh As (Ctrl+Shift+E, mainwindow_Init.cpp), a file name typed into Qt's
    save dialog, and the saving options dialog accepted with its defaults (OK is its default
    button), as a user saves. The file is then checked on its own: every face has per-wedge
    texture coordinates, none is flipped or degenerate in UV (tests/meshlab/check_obj_uv.py)."""
    exported = os.path.join(workdir, args.export)
    inside = exported[len(args.root):] if args.root else exported
    gui.focus(gui.main)
    gui.key("ctrl+shift+e")
    save = gui.wait_window(r'^Save ".*" Layer$')[0]
    gui.screenshot("05_export_file.png")
    gui.focus(save)
    # The file name field has the focus and holds the mesh's own name, selected.
    gui.key("ctrl+a", "BackSpace")
    gui.run("xdotool", "type", "--delay", "20", inside)
    gui.key("Return")
    options = gui.wait_window(r"^Choose Saving Options for")[0]
    gui.screenshot("06_export_options.png")
    gui.focus(options)
    gui.key("Return")
    gui.wait_for("the saving options dialog to close",
                 lambda: not gui.windows(r"^Choose Saving Options for"))
    gui.wait_for("'Saved Mesh' in meshlab.log",
                 lambda: re.search(r"Saved Mesh .*%s" % re.escape(args.export), gui.log_text()))
    check = subprocess.run([sys.executable, os.path.join(os.path.dirname(os.path.abspath(__file__)),
                                                         "..", "meshlab", "check_obj_uv.py"),
                            exported] + (["--atlas"] if args.filter == "atlas" else []),
                           capture_output=True, text=True, timeout=gui.remaining(60))
    shutil.copyfile(exported, os.path.join(args.out, args.export))
    if check.returncode != 0:
        raise CheckFailed("the exported %s: %s" % (args.export, (check.stdout + check.stderr).strip()))
    passed("export", "%s saved with the export dialog's defaults: %s"
           % (args.export, check.stdout.strip().splitlines()[-1] if check.stdout.strip() else "ok"))


def largest_child(gui, window):
    """Absolute (x, y, w, h) of the largest direct child window, from xwininfo."""
    out = gui.run("xwininfo", "-children", "-id", str(window))
    best = None
    for m in re.finditer(r"(\d+)x(\d+)\+-?\d+\+-?\d+\s+\+(-?\d+)\+(-?\d+)", out):
        w, h, x, y = (int(v) for v in m.groups())
        if (w, h) != SCREEN and (best is None or w * h > best[2] * best[3]):
            best = (x, y, w, h)
    return best if best and best[2] > 200 and best[3] > 200 else None


def main():
    global MIN_RED
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--plugin", required=True,
                        help="the 2020.09 libfilter_straightest_param.so")
    parser.add_argument("--mesh", required=True,
                        help="a disk-shaped mesh (.off); a closed one with --filter atlas")
    parser.add_argument("--filter", choices=("patch", "atlas"), default="patch",
                        help="which of our two filters to run (default: the patch filter)")
    parser.add_argument("--out", required=True,
                        help="folder for screenshots, logs, work folder (replaces earlier ones)")
    parser.add_argument("--prefix", help="private MeshLab 2020.09 prefix (default OUT/../gui-prefix)")
    parser.add_argument("--root", help="a Debian root with a newer MeshLab (scripts/make-meshlab-root.sh)")
    parser.add_argument("--meshlab-version", choices=sorted(TEXTURE_FILTERS), default="2020.09",
                        help="the MeshLab version under test (2022.02 and 2025.07 need --root)")
    parser.add_argument("--export", metavar="NAME.obj",
                        help="after Apply, save the mesh as NAME.obj through File -> Export Mesh "
                        "As with the dialogs' defaults, and check the file's per-wedge UVs")
    parser.add_argument("--watch-progress", action="store_true",
                        help="read the status bar's progress bar while the filter runs, and "
                        "report the longest wait between its moves (progress.txt, "
                        "progress_NN.png)")
    parser.add_argument("--min-red", type=float, default=MIN_RED * 100,
                        help="percent of the 3D view's pixels that must stay red (the grid lines) "
                        "to count as our checkerboard (default %g; lower for meshes of millions "
                        "of faces, whose squares are a few pixels)" % (MIN_RED * 100))
    parser.add_argument("--apply-timeout", type=float, default=120.0,
                        help="seconds the filter may run (default 120; more for large meshes)")
    parser.add_argument("--total-timeout", type=float, default=TOTAL_TIMEOUT,
                        help="seconds the whole run may take (default %d)" % TOTAL_TIMEOUT)
    parser.add_argument("--install", choices=("user", "system"), default="user",
                        help="with --root: the per-user plugin folder of a fresh HOME, or the "
                        "root's system folder (removed again at the end)")
    args = parser.parse_args()
    MIN_RED = args.min_red / 100
    if (args.root is None) != (args.meshlab_version == "2020.09"):
        parser.error("--root goes with --meshlab-version 2022.02 or 2025.07")
    if args.root:
        args.root = os.path.abspath(args.root)
    args.out = os.path.abspath(args.out)
    args.plugin = os.path.abspath(args.plugin)
    args.mesh = os.path.abspath(args.mesh)
    args.prefix = os.path.abspath(args.prefix or os.path.join(args.out, "..", "gui-prefix"))

    missing = [t for t in ("Xvfb", "xdotool", "xwininfo", "import", "convert", "nice")
               + (("unshare", "chroot") if args.root else ()) if shutil.which(t) is None]
    if missing:
        print("FAIL: missing tools: %s (scripts/install-deps.sh installs them)" % " ".join(missing))
        return 2
    for path in (args.plugin, args.mesh):
        if not os.path.isfile(path):
            print("FAIL: %s missing" % path)
            return 1

    # Remove only what an earlier run of this script left: OUT may be any folder.
    os.makedirs(args.out, exist_ok=True)
    for name in os.listdir(args.out):
        path = os.path.join(args.out, name)
        if name in ("work", "xdg") and os.path.isdir(path):
            shutil.rmtree(path)
        elif re.fullmatch(r"(\d\d_\w+|failure)\.png|(meshlab|xvfb)\.log|result\.txt|layout\.json|"
                          + re.escape(texture_name(args)), name):
            os.remove(path)
    gui = Gui(args.out, args.total_timeout)

    def on_signal(signum, _frame):
        raise CheckFailed("stopped by signal %d" % signum)
    signal.signal(signal.SIGTERM, on_signal)
    signal.signal(signal.SIGINT, on_signal)
    signal.signal(signal.SIGHUP, on_signal)

    status = 0
    try:
        run_test(args, gui)
    except (CheckFailed, subprocess.CalledProcessError, subprocess.TimeoutExpired) as e:
        status = 1
        RESULTS.append("FAIL " + str(e))
        log_line("FAIL: %s" % e)
        if gui.env is not None and gui.xvfb is not None and gui.xvfb.poll() is None:
            try:
                gui.run("import", "-window", "root", os.path.join(args.out, "failure.png"),
                        timeout=20, check=False)
                log_line("screen at failure: %s" % os.path.join(args.out, "failure.png"))
            except Exception:  # the screenshot is a courtesy; the failure is already recorded
                pass
    finally:
        for signum in (signal.SIGTERM, signal.SIGINT, signal.SIGHUP):
            signal.signal(signum, signal.SIG_IGN)  # let the cleanup finish
        gui.stop()
        if gui.root_folder:
            # Keep what a reader of a failure needs, then leave the cached root as it was.
            texture = os.path.join(gui.root_folder, "work", texture_name(args))
            if os.path.isfile(texture):
                shutil.copyfile(texture, os.path.join(args.out, texture_name(args)))
            shutil.rmtree(gui.root_folder, ignore_errors=True)
        if gui.system_plugin and os.path.exists(gui.system_plugin):
            os.remove(gui.system_plugin)
    seconds = time.monotonic() - gui.started
    RESULTS.append("%s in %.1f s" % ("PASSED" if status == 0 else "FAILED", seconds))
    with open(os.path.join(args.out, "result.txt"), "w") as f:
        f.write("\n".join(RESULTS) + "\n")
    with open(os.path.join(args.out, "layout.json"), "w") as f:
        json.dump(LAYOUT, f, indent=1)
    if status:
        log_meshlab = os.path.join(args.out, "meshlab.log")
        if os.path.exists(log_meshlab):
            with open(log_meshlab, "rb") as f:
                tail = f.read().decode("utf-8", "replace").splitlines()[-15:]
            log_line("--- last lines of meshlab.log ---\n" + "\n".join(tail))
    log_line("%s in %.1f s; screenshots in %s" % ("PASSED" if status == 0 else "FAILED",
                                                  seconds, args.out))
    return status


if __name__ == "__main__":
    sys.exit(main())
