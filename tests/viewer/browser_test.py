#!/usr/bin/python3
"""The viewer in a real browser: headless Chromium (software WebGL) on a small run's frames.

  browser_test.py CLOTHLAB PLUGIN_DIR WORK_DIR CASE
  CASE: cloth-drawn-and-moving   screenshots at t = 0 and t = 0.8 s: in each, enough pixels of
                                 the 3D view differ from the background around its centre,
                                 and the two differ from each other (the cloth moved)
        side-by-side             two runs (rk4, verlet): a cloth in each half of the view
        no-frames                `clothlab view` on a folder without frames: one line, exit 1
        mutant-draws-nothing     the same page with its render call removed: the cloth check
                                 must find no cloth (the check can fail)
        collider-drawn           a small drape over a larger sphere: the view with its colliders and the
                                 same view with them hidden (colliders=0) differ in enough
                                 pixels, below the cloth's top, and the sphere's pixels have
                                 the collider colour's hue
        mutant-draws-no-collider the page with the colliders never added to the scene: the
                                 collider check must find none (the check can fail)
The screenshots stay in WORK_DIR (printed) as test artefacts.
"""
import os
import shutil
import subprocess
import sys

from PIL import Image, ImageChops

CLOTHLAB, PLUGIN_DIR, WORK, CASE = sys.argv[1:5]
WIDTH, HEIGHT, PANEL = 1000, 600, 340  # window and the side panel's width (viewer.css)
BACKGROUND = (0x1D, 0x20, 0x26)  # viewer.js BACKGROUND


def fail(message):
    print("FAIL:", message)
    sys.exit(1)


def run(*arguments):
    result = subprocess.run(arguments, capture_output=True, text=True, timeout=300)
    if result.returncode != 0:
        fail(f"{' '.join(arguments)} exited {result.returncode}: {result.stderr}")
    return result


def frames(out, integrator):
    folder = os.path.join(out, integrator)
    run(CLOTHLAB, "--plugin-path", PLUGIN_DIR, "--integrator", integrator, "--scenario", "flag",
        "--set", "scenario.rows=30", "--set", "scenario.cols=30", "--duration", "1",
        "--set", "frames.rate=30", "--frames", folder, "--quiet")
    return folder


def screenshot(page, query, path):
    profile = path + ".profile"
    shutil.rmtree(profile, ignore_errors=True)
    run("chromium", "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
        "--no-first-run", "--disable-background-networking", "--disable-component-update",
        "--disable-sync", f"--user-data-dir={profile}", "--use-angle=swiftshader",
        "--enable-unsafe-swiftshader", f"--window-size={WIDTH},{HEIGHT}",
        "--virtual-time-budget=5000", f"--screenshot={path}", f"file://{page}?{query}")
    shutil.rmtree(profile, ignore_errors=True)
    print("screenshot:", path)
    return Image.open(path).convert("RGB")


def cloth_pixels(image, box):
    """Pixels in box (left, top, right, bottom) that are clearly not background."""
    region = image.crop(box)
    background = Image.new("RGB", region.size, BACKGROUND)
    difference = ImageChops.difference(region, background).convert("L")
    mask = difference.point(lambda d: 255 if d > 24 else 0)
    return mask, sum(1 for p in mask.getdata() if p)


def check_cloth(image, box, name):
    mask, count = cloth_pixels(image, box)
    area = (box[2] - box[0]) * (box[3] - box[1])
    if count < 0.03 * area:
        fail(f"{name}: only {count} of {area} pixels differ from the background: no cloth drawn")
    left, top, right, bottom = mask.getbbox()
    centre_x, centre_y = (left + right) / 2, (top + bottom) / 2
    width, height = box[2] - box[0], box[3] - box[1]
    if not (0.2 * width < centre_x < 0.8 * width and 0.2 * height < centre_y < 0.8 * height):
        fail(f"{name}: the drawing's centre ({centre_x:.0f}, {centre_y:.0f}) is off the view's "
             f"middle ({width}x{height})")
    print(f"{name}: {count} of {area} view pixels are cloth ({100 * count / area:.1f} %)")
    return count


def drape_view(out):
    folder = os.path.join(out, "drape")
    run(CLOTHLAB, "--plugin-path", PLUGIN_DIR, "--integrator", "xpbd", "--scenario", "drape",
        "--set", "scenario.rows=20", "--set", "scenario.cols=20", "--set", "scenario.width=0.4",
        "--set", "scenario.height=0.4", "--duration", "0.5",
        "--set", "frames.rate=30", "--frames", folder, "--quiet")
    view = os.path.join(out, "view")
    run(CLOTHLAB, "view", folder, "--out", view)
    return view


def collider_pixels(view, out):
    """View pixels that change when the colliders are hidden, and their bounding box."""
    page = os.path.join(view, "index.html")
    shown = screenshot(page, "t=0.5&paused=1", os.path.join(out, "colliders.png"))
    hidden = screenshot(page, "t=0.5&paused=1&colliders=0", os.path.join(out, "no-colliders.png"))
    box = (0, 0, WIDTH - PANEL, HEIGHT)
    changed = ImageChops.difference(shown.crop(box), hidden.crop(box)).convert("L")
    mask = changed.point(lambda d: 255 if d > 24 else 0)
    return shown.crop(box), mask, sum(1 for p in mask.getdata() if p)


def collider_drawn():
    out = os.path.join(WORK, "collider")
    shutil.rmtree(out, ignore_errors=True)
    image, mask, count = collider_pixels(drape_view(out), out)
    area = (WIDTH - PANEL) * HEIGHT
    if count < 0.02 * area:
        fail(f"only {count} of {area} view pixels change when the colliders are hidden: no "
             "collider drawn")
    # The sphere lies under the cloth: its pixels reach lower in the view than the cloth's top.
    _, top, _, bottom = mask.getbbox()
    if bottom < HEIGHT / 2:
        fail(f"the collider's pixels end at row {bottom}, above the view's middle")
    # Its colour (viewer.js COLLIDER_COLOUR, shaded): warm grey, red >= green >= blue.
    warm = sum(1 for (r, g, b), m in zip(image.getdata(), mask.getdata())
               if m and r + 4 >= g >= b - 4 and r > b)
    if warm < 0.5 * count:
        fail(f"{warm} of the {count} collider pixels have the collider colour's hue")
    print(f"ok: {count} of {area} view pixels are the collider (rows {top}-{bottom}), "
          f"{warm} in its colour")


def mutant_draws_no_collider():
    out = os.path.join(WORK, "collider-mutant")
    shutil.rmtree(out, ignore_errors=True)
    view = drape_view(out)
    script = os.path.join(view, "viewer.js")
    with open(script) as stream:
        text = stream.read()
    add_call = "run.scene.add(placed);"
    if add_call not in text:
        fail(f"viewer.js has no '{add_call}' to remove")
    with open(script, "w") as stream:
        stream.write(text.replace(add_call, ""))
    _, _, count = collider_pixels(view, out)
    area = (WIDTH - PANEL) * HEIGHT
    if count >= 0.02 * area:
        fail(f"a page that draws no collider passes the collider check ({count} of {area} pixels)")
    print(f"ok: the page without colliders in its scene changes {count} of {area} pixels")


def cloth_drawn_and_moving():
    out = os.path.join(WORK, "single")
    shutil.rmtree(out, ignore_errors=True)
    folder = frames(out, "rk4")
    page = run(CLOTHLAB, "view", folder, "--out", os.path.join(out, "view")).stdout
    page = page.split("file://", 1)[1].split()[0]
    view = (0, 0, WIDTH - PANEL, HEIGHT)
    early = screenshot(page, "t=0&paused=1", os.path.join(out, "t0.png"))
    late = screenshot(page, "t=0.8&paused=1", os.path.join(out, "t0.8.png"))
    check_cloth(early, view, "t = 0")
    check_cloth(late, view, "t = 0.8")
    moved = ImageChops.difference(early.crop(view), late.crop(view)).convert("L")
    changed = sum(1 for p in moved.getdata() if p > 24)
    if changed < 0.01 * (view[2] * view[3]):
        fail(f"only {changed} view pixels differ between t = 0 and t = 0.8: the cloth did not move")
    print(f"ok: {changed} view pixels changed between t = 0 and t = 0.8 s")


def side_by_side():
    out = os.path.join(WORK, "side-by-side")
    shutil.rmtree(out, ignore_errors=True)
    runs = [frames(out, "rk4"), frames(out, "verlet")]
    page = run(CLOTHLAB, "view", *runs, "--out", os.path.join(out, "view")).stdout
    page = page.split("file://", 1)[1].split()[0]
    image = screenshot(page, "t=0.5&paused=1&layout=side", os.path.join(out, "side.png"))
    half = (WIDTH - PANEL) // 2
    check_cloth(image, (0, 0, half, HEIGHT), "left pane (rk4)")
    check_cloth(image, (half, 0, 2 * half, HEIGHT), "right pane (verlet)")
    print("ok: one cloth in each pane")


def mutant_draws_nothing():
    out = os.path.join(WORK, "mutant")
    shutil.rmtree(out, ignore_errors=True)
    folder = frames(out, "rk4")
    view = os.path.join(out, "view")
    run(CLOTHLAB, "view", folder, "--out", view)
    script = os.path.join(view, "viewer.js")
    with open(script) as stream:
        text = stream.read()
    render_call = "renderer.render(run.scene, camera);"
    if render_call not in text:
        fail(f"viewer.js has no '{render_call}' to remove")
    with open(script, "w") as stream:
        stream.write(text.replace(render_call, ""))
    image = screenshot(os.path.join(view, "index.html"), "t=0.5&paused=1",
                       os.path.join(out, "nothing-drawn.png"))
    _, count = cloth_pixels(image, (0, 0, WIDTH - PANEL, HEIGHT))
    area = (WIDTH - PANEL) * HEIGHT
    if count >= 0.03 * area:
        fail(f"a page that draws no cloth passes the cloth check ({count} of {area} pixels)")
    print(f"ok: the page without its render call shows {count} of {area} non-background pixels")


def no_frames():
    empty = os.path.join(WORK, "empty")
    os.makedirs(empty, exist_ok=True)
    result = subprocess.run([CLOTHLAB, "view", empty, "--out", os.path.join(WORK, "no-view")],
                            capture_output=True, text=True)
    lines = result.stderr.splitlines()
    if result.returncode != 1 or len(lines) != 1 or "no frames" not in lines[0]:
        fail(f"exit {result.returncode}, stderr {result.stderr!r}")
    print("ok:", lines[0])


{"cloth-drawn-and-moving": cloth_drawn_and_moving, "side-by-side": side_by_side,
 "no-frames": no_frames, "mutant-draws-nothing": mutant_draws_nothing,
 "collider-drawn": collider_drawn, "mutant-draws-no-collider": mutant_draws_no_collider}[CASE]()
