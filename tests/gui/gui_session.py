"""What every window script under tests/gui shares (they run inside a real
Blender under xvfb-run, not -b): the import paths, the output folder from
`-- OUT_DIR`, the largest 3D View, viewport screenshots as pixels, and the
step runner that drives a script from a timer (a window needs its event loop
between steps) and writes the stats as JSON for the pytest side to assert on."""
import json
import os
import shutil
import sys
import traceback

import bpy
import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.path.join(REPO, os.environ.get("PARAMORPH_BUILD_DIR", "build"), "python")
for _path in (BUILD, os.path.join(REPO, "addon"), os.path.join(REPO, "blend_samples")):
    sys.path.insert(0, _path)
OUT = os.path.abspath(sys.argv[sys.argv.index("--") + 1])

stats = {}


def view3d():
    """(window, area, region) of the largest 3D View."""
    window = bpy.context.window_manager.windows[0]
    area = max((a for a in window.screen.areas if a.type == "VIEW_3D"), key=lambda a: a.width * a.height)
    region = next(r for r in area.regions if r.type == "WINDOW")
    return window, area, region


def centre_of_region():
    """Window coordinates of the middle of the largest 3D View."""
    region = view3d()[2]
    return region.x + region.width // 2, region.y + region.height // 2


def simulate(kind, value="PRESS", xy=None, **keys):
    """A simulated input event (blender --enable-event-simulate) at xy, by
    default the middle of the 3D View."""
    x, y = xy if xy is not None else centre_of_region()
    view3d()[0].event_simulate(type=kind, value=value, x=x, y=y, **keys)


def screenshot_rgb(name):
    """Screenshot of the 3D View saved as OUT/<name>.png; its pixels, (n, 3) float RGB."""
    window, area, region = view3d()
    area.tag_redraw()
    path = os.path.join(OUT, f"{name}.png")
    with bpy.context.temp_override(window=window, area=area, region=region):
        bpy.ops.screen.screenshot_area(filepath=path)
    image = bpy.data.images.load(path)
    w, h = image.size
    px = np.empty(w * h * 4, dtype=np.float32)
    image.pixels.foreach_get(px)
    return px.reshape(-1, 4)[:, :3]


def keep_for_readme(name, as_name=None):
    """Copies OUT/<name>.png to $PARAMORPH_SCREENSHOTS/<as_name or name>.png
    when that is set (scripts/screenshots.sh sets it to docs/screenshots,
    which the README shows): the README's pictures are the tests' own."""
    folder = os.environ.get("PARAMORPH_SCREENSHOTS")
    if folder:
        os.makedirs(folder, exist_ok=True)
        shutil.copyfile(os.path.join(OUT, f"{name}.png"), os.path.join(folder, f"{as_name or name}.png"))


def run_steps(steps, report):
    """Runs steps (callables; None waits one tick) half a second apart; an
    exception records its traceback in stats["error"] and skips to the end,
    which writes OUT/<report> and quits Blender. The list itself is the
    queue: a step that waits re-inserts itself with steps.insert(0, step)."""
    def finish():
        with open(os.path.join(OUT, report), "w") as f:
            json.dump(stats, f)
        bpy.ops.wm.quit_blender()

    queue = steps  # not a copy: waiting steps insert themselves at its front
    queue.append(finish)

    def tick():
        try:
            step = queue.pop(0)
            if step is not None:
                step()
        except Exception:
            stats["error"] = traceback.format_exc()
            queue[:] = [finish]
        return 0.5 if queue else None

    os.makedirs(OUT, exist_ok=True)
    bpy.app.timers.register(tick, first_interval=1.0)


def wait_while(steps, still_waiting, record, limit_s=120.0):
    """A step that repeats (by re-inserting itself at the queue's front) while
    still_waiting() is true, for at most limit_s seconds of wall time, and
    writes how long it waited into record["waited_s"]. Time, not a count of
    ticks: a loaded machine ticks the timer late and computes slowly."""
    import time
    started = []

    def wait():
        now = time.monotonic()
        if not started:
            started.append(now)
        record["waited_s"] = round(now - started[0], 2)
        if not still_waiting():
            return
        if now - started[0] < limit_s:
            steps.insert(0, wait)
            return
        # Gave up: what was still running, for the failure message (a hang
        # or a slow machine), and every Python thread's stack beside the stats.
        import faulthandler
        from paramorph import jobs
        record["timed_out"] = True
        record["running"] = [(job.stage, round(job.fraction, 3)) for job in jobs.running()]
        with open(os.path.join(OUT, "stacks.txt"), "a") as f:
            faulthandler.dump_traceback(f, all_threads=True)
    return wait
