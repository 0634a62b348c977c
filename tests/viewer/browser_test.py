#!/usr/bin/python3
"""The viewer in a real browser: headless Chromium (software WebGL) on a small run's frames.

  browser_test.py CLOTHLAB PLUGIN_DIR WORK_DIR CASE
  CASE: cloth-drawn-and-moving   screenshots at t = 0 and t = 0.8 s: in each, enough pixels of
                                 the 3D view differ from the background around its centre,
                                 and the two differ from each other (the cloth moved)
        side-by-side             two runs (rk4, verlet): a cloth in each half of the view
        mesh-drawn               a cloth that is a triangle mesh (the mesh scenario's disc.obj,
                                 hanging from its centre): at t = 0.5 at least 1 % of the view's
                                 pixels are cloth, around its centre
        no-frames                `clothlab view` on a folder without frames: one line, exit 1
        mutant-draws-nothing     the same page with its render call removed: the cloth check
                                 must find no cloth (the check can fail)
        collider-drawn           a small drape over a larger sphere: the view with its colliders and the
                                 same view with them hidden (colliders=0) differ in enough
                                 pixels, below the cloth's top, and the sphere's pixels have
                                 the collider colour's hue
        mutant-draws-no-collider the page with the colliders never added to the scene: the
                                 collider check must find none (the check can fail)
        cape-frames              the cape run the three cape cases view (run once, first)
        cape-and-character       a small cape run, 1 s of the character starting to walk along
                                 +x; at t = 0 and t = 1: the pixels that change when the
                                 colliders are hidden are many and in the collider colour's hue
                                 (the character), cloth pixels lie around it with their centre
                                 behind it (the cape), and the character's centre moves across
                                 the view the way the run's torso walks along the camera's right
                                 axis (runs.js), by at least 5 % of the view
        mutant-character-frozen  the page drawing every collider at its first pose: the motion
                                 check must fail, and the cape check (the cape walked on, ahead
                                 of the frozen character); the character is still found
        mutant-draws-no-cape     the page with the cloth never added to the scene: the cape
                                 check must fail, the character and motion checks pass
        folder-name-is-text      a run whose frames folder is named as markup with a script
                                 (INJECTED): the page shows the name as text and the script
                                 does not run
        mutant-name-as-markup    the page inserting the folder name as markup: the injection
                                 check must find the script ran (the check can fail)
The screenshots stay in WORK_DIR (printed) as test artefacts.
"""
import html
import json
import math
import os
import re
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


def chromium_start(page, query, profile, *options):
    """Starts headless Chromium (software WebGL) on the page with the output options; most of a
    run is Chromium starting and stopping, not drawing, so a case starts its runs at once."""
    shutil.rmtree(profile, ignore_errors=True)
    arguments = ["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic",
                 "--no-first-run", "--disable-background-networking", "--disable-component-update",
                 "--disable-sync", f"--user-data-dir={profile}", "--use-angle=swiftshader",
                 "--enable-unsafe-swiftshader", f"--window-size={WIDTH},{HEIGHT}",
                 "--virtual-time-budget=5000", *options, f"file://{page}?{query}"]
    process = subprocess.Popen(arguments, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    return arguments, profile, process


def chromium_output(started):
    """The standard output of a Chromium run chromium_start started, once it ended well."""
    arguments, profile, process = started
    try:
        stdout, stderr = process.communicate(timeout=300)
    except subprocess.TimeoutExpired:
        process.kill()
        process.communicate()
        fail(f"{' '.join(arguments)} ran over 300 s")
    shutil.rmtree(profile, ignore_errors=True)
    if process.returncode != 0:
        fail(f"{' '.join(arguments)} exited {process.returncode}: {stderr}")
    return stdout


def screenshots(page, shots):
    """The page's screenshots, one per (query, path), taken by Chromium runs at the same time."""
    started = [chromium_start(page, query, path + ".profile", f"--screenshot={path}")
               for query, path in shots]
    for run_started in started:
        chromium_output(run_started)
    images = []
    for _, path in shots:
        print("screenshot:", path)
        images.append(Image.open(path).convert("RGB"))
    return images


def screenshot(page, query, path):
    return screenshots(page, [(query, path)])[0]


def page_dom_start(page, query, work):
    """Starts Chromium on the page to print its document after its scripts ran (--dump-dom);
    chromium_output gives the document."""
    return chromium_start(page, query, os.path.join(work, "dom.profile"), "--dump-dom")


def differing(first, second):
    """The mask of the pixels where two images clearly differ in any channel (a brightness
    difference would miss a dark blue cloth on the dark background)."""
    red, green, blue = ImageChops.difference(first, second).split()
    largest = ImageChops.lighter(ImageChops.lighter(red, green), blue)
    return largest.point(lambda d: 255 if d > 24 else 0)


def cloth_pixels(image, box):
    """Pixels in box (left, top, right, bottom) that are clearly not background."""
    region = image.crop(box)
    mask = differing(region, Image.new("RGB", region.size, BACKGROUND))
    return mask, sum(1 for p in mask.getdata() if p)


def check_cloth(image, box, name, least_share=0.03):
    mask, count = cloth_pixels(image, box)
    area = (box[2] - box[0]) * (box[3] - box[1])
    if count < least_share * area:
        fail(f"{name}: only {count} of {area} pixels differ from the background: no cloth drawn")
    left, top, right, bottom = mask.getbbox()
    centre_x, centre_y = (left + right) / 2, (top + bottom) / 2
    width, height = box[2] - box[0], box[3] - box[1]
    if not (0.2 * width < centre_x < 0.8 * width and 0.2 * height < centre_y < 0.8 * height):
        fail(f"{name}: the drawing's centre ({centre_x:.0f}, {centre_y:.0f}) is off the view's "
             f"middle ({width}x{height})")
    print(f"{name}: {count} of {area} view pixels are cloth ({100 * count / area:.1f} %)")
    return count


def mutate_page(view, code, replacement):
    """A mutant of the page written by `clothlab view`: `code` in its viewer.js replaced."""
    script = os.path.join(view, "viewer.js")
    with open(script) as stream:
        text = stream.read()
    if code not in text:
        fail(f"viewer.js has no '{code}' to replace")
    with open(script, "w") as stream:
        stream.write(text.replace(code, replacement))


def drape_view(out):
    folder = os.path.join(out, "drape")
    run(CLOTHLAB, "--plugin-path", PLUGIN_DIR, "--integrator", "xpbd", "--scenario", "drape",
        "--set", "scenario.rows=20", "--set", "scenario.cols=20", "--set", "scenario.width=0.4",
        "--set", "scenario.height=0.4", "--frame-rate", "1000", "--substeps", "40",
        "--duration", "0.5",
        "--set", "frames.rate=30", "--frames", folder, "--quiet")
    view = os.path.join(out, "view")
    run(CLOTHLAB, "view", folder, "--out", view)
    return view


def collider_shots(out, t, name):
    """The (query, path) of the view at time t with its colliders and with them hidden
    (colliders=0)."""
    return [(f"t={t}&paused=1", os.path.join(out, f"{name}colliders.png")),
            (f"t={t}&paused=1&colliders=0", os.path.join(out, f"{name}no-colliders.png"))]


def collider_mask(shown, hidden):
    """The view with its colliders, the mask of the pixels that change when the colliders are
    hidden, their count, and the view with the colliders hidden."""
    box = (0, 0, WIDTH - PANEL, HEIGHT)
    mask = differing(shown.crop(box), hidden.crop(box))
    return shown.crop(box), mask, sum(1 for p in mask.getdata() if p), hidden.crop(box)


def collider_pixels(view, out, t=0.5, name=""):
    """collider_mask of the view at time t."""
    shots = collider_shots(out, t, name)
    return collider_mask(*screenshots(os.path.join(view, "index.html"), shots))


def collider_coloured(image, mask):
    """How many of the mask's pixels have the collider colour's hue (viewer.js COLLIDER_COLOUR,
    shaded): warm grey, red >= green >= blue."""
    return sum(1 for (r, g, b), m in zip(image.getdata(), mask.getdata())
               if m and r + 4 >= g >= b - 4 and r > b)


def collider_drawn():
    out = os.path.join(WORK, "collider")
    shutil.rmtree(out, ignore_errors=True)
    image, mask, count, _ = collider_pixels(drape_view(out), out)
    area = (WIDTH - PANEL) * HEIGHT
    if count < 0.02 * area:
        fail(f"only {count} of {area} view pixels change when the colliders are hidden: no "
             "collider drawn")
    # The sphere lies under the cloth: its pixels reach lower in the view than the cloth's top.
    _, top, _, bottom = mask.getbbox()
    if bottom < HEIGHT / 2:
        fail(f"the collider's pixels end at row {bottom}, above the view's middle")
    warm = collider_coloured(image, mask)
    if warm < 0.5 * count:
        fail(f"{warm} of the {count} collider pixels have the collider colour's hue")
    print(f"ok: {count} of {area} view pixels are the collider (rows {top}-{bottom}), "
          f"{warm} in its colour")


def mutant_draws_no_collider():
    out = os.path.join(WORK, "collider-mutant")
    shutil.rmtree(out, ignore_errors=True)
    view = drape_view(out)
    mutate_page(view, "run.scene.add(placed);", "")
    _, _, count, _ = collider_pixels(view, out)
    area = (WIDTH - PANEL) * HEIGHT
    if count >= 0.02 * area:
        fail(f"a page that draws no collider passes the collider check ({count} of {area} pixels)")
    print(f"ok: the page without colliders in its scene changes {count} of {area} pixels")


# The cape run: the character stands at t = 0 and by CAPE_LATE has walked about 1.1 m along +x
# (cape.cpp's script: 0.5 s from standing to 1.5 m/s, then walking straight).
CAPE_LATE = 1.0
def camera_azimuth(dom):
    """The page's starting orbit azimuth, which it publishes on its root element (data-orbit) of
    its document after its scripts ran: the camera's right axis is (cos, 0, -sin) of it."""
    match = re.search(r'<html[^>]*data-orbit="([^"]*)"', dom)
    if match is None:
        fail("the cape's index.html: no data-orbit on the page's root element to read")
    return float(json.loads(html.unescape(match.group(1)))["azimuth"])


CAPE_FRAMES = os.path.join(WORK, "cape-frames")


def cape_frames():
    """The cape run the three cape cases view (a CTest fixture runs it once for them)."""
    shutil.rmtree(CAPE_FRAMES, ignore_errors=True)
    run(CLOTHLAB, "--plugin-path", PLUGIN_DIR, "--integrator", "xpbd", "--scenario", "cape",
        "--set", "scenario.rows=16", "--set", "scenario.cols=10", "--frame-rate", "1000",
        "--substeps", "40", "--duration", str(CAPE_LATE),
        "--set", "frames.rate=30", "--frames", CAPE_FRAMES, "--quiet")
    print("ok: the cape's frames are in", CAPE_FRAMES)


def cape_view(out):
    if not os.path.isdir(CAPE_FRAMES):
        fail(f"no cape frames in {CAPE_FRAMES}: the case cape-frames runs first (a CTest fixture)")
    view = os.path.join(out, "view")
    run(CLOTHLAB, "view", CAPE_FRAMES, "--out", view)
    return view


def walk_rightwards(view, dom):
    """How far the torso (the run's first collider) goes from the first to the last frame along
    the camera's right axis, in metres, from the runs.js the page plays and the page's document
    after its scripts ran."""
    with open(os.path.join(view, "runs.js")) as stream:
        text = stream.read()
    opening = "Object.assign("
    head, _ = json.JSONDecoder().raw_decode(text, text.index(opening) + len(opening))
    first, last = head["collider_poses"][0], head["collider_poses"][-1]
    azimuth = camera_azimuth(dom)
    return (last[0] - first[0]) * math.cos(azimuth) - (last[2] - first[2]) * math.sin(azimuth)


def centroid(mask):
    width, count, x, y = mask.size[0], 0, 0, 0
    for k, p in enumerate(mask.getdata()):
        if p:
            count, x, y = count + 1, x + k % width, y + k // width
    return (x / count, y / count) if count else None


def cape_problems(view, out):
    """What the cape's view fails of: the character drawn, the cape drawn behind it, the character
    moving across the view the way its torso walks in the run; None for each check it passes."""
    area = (WIDTH - PANEL) * HEIGHT
    problems = {"character": None, "cape": None, "motion": None}
    centres = []
    page = os.path.join(view, "index.html")
    dom = page_dom_start(page, "paused=1", view)
    times = (0, CAPE_LATE)
    shots = [shot for t in times for shot in collider_shots(out, t, f"cape-t{t}-")]
    images = screenshots(page, shots)
    # The character faces the way it walks: its back, and the cape, are on the other side.
    walk = walk_rightwards(view, chromium_output(dom))
    if abs(walk) < 0.5:
        fail(f"the run's torso goes only {walk:.2f} m across the view: the cape run is too short")
    behind = "left" if walk > 0 else "right"
    for k, t in enumerate(times):
        image, mask, count, hidden = collider_mask(images[2 * k], images[2 * k + 1])
        if count < 0.01 * area:
            problems["character"] = problems["character"] or (
                f"t = {t}: only {count} of {area} view pixels change when the colliders are "
                "hidden: no character drawn")
            continue
        warm = collider_coloured(image, mask)
        if warm < 0.5 * count:
            problems["character"] = problems["character"] or (
                f"t = {t}: {warm} of the {count} character pixels have the collider colour's hue")
        centre = centroid(mask)
        centres.append(centre)
        # The cape: cloth pixels, with the character hidden, within the character's bounding box
        # grown on every side by its larger side (the cape is about as long as the character is
        # tall), and their centre behind the character's.
        left, top, right, bottom = mask.getbbox()
        margin = max(right - left, bottom - top)
        near = (max(0, left - margin), max(0, top - margin), min(WIDTH - PANEL, right + margin),
                min(HEIGHT, bottom + margin))
        cloth, cloth_count = cloth_pixels(hidden, near)
        cloth_centre = centroid(cloth)
        if cloth_count < 0.2 * count:
            problems["cape"] = problems["cape"] or (
                f"t = {t}: only {cloth_count} cloth pixels near the character ({count} pixels): "
                "no cape drawn")
        elif (near[0] + cloth_centre[0] - centre[0]) * walk >= 0:
            problems["cape"] = problems["cape"] or (
                f"t = {t}: the cape's centre (column {near[0] + cloth_centre[0]:.0f}) is not "
                f"behind ({behind} of) the character's (column {centre[0]:.0f})")
        print(f"t = {t}: {count} character pixels ({warm} in its colour) centred at "
              f"({centre[0]:.0f}, {centre[1]:.0f}); {cloth_count} cape pixels near it")
    if len(centres) == 2:
        dx, dy = centres[1][0] - centres[0][0], centres[1][1] - centres[0][1]
        print(f"the character's centre moved ({dx:.0f}, {dy:.0f}) pixels from t = 0 to "
              f"t = {CAPE_LATE}; its torso walked {walk:.2f} m to the camera's right")
        if dx * walk <= 0 or abs(dx) < 0.05 * (WIDTH - PANEL) or abs(dy) > abs(dx):
            problems["motion"] = (
                f"the character's centre moved ({dx:.0f}, {dy:.0f}) pixels from t = 0 to "
                f"t = {CAPE_LATE}, not {'right' if walk > 0 else 'left'} with its walk of "
                f"{abs(walk):.2f} m by at least {0.05 * (WIDTH - PANEL):.0f} pixels")
    return problems


def cape_and_character():
    out = os.path.join(WORK, "cape")
    shutil.rmtree(out, ignore_errors=True)
    problems = cape_problems(cape_view(out), out)
    for problem in problems.values():
        if problem:
            fail(problem)
    print("ok: the character and its cape are drawn, and the character walks as in the run")


def cape_mutant(name, code, replacement, caught, passed):
    """The cape's page with `code` in viewer.js replaced: the checks in `caught` must fail and
    those in `passed` must still pass (the mutant breaks what it means to, not everything)."""
    out = os.path.join(WORK, name)
    shutil.rmtree(out, ignore_errors=True)
    view = cape_view(out)
    mutate_page(view, code, replacement)
    problems = cape_problems(view, out)
    for check in caught:
        if not problems[check]:
            fail(f"the mutant passes the {check} check")
        print(f"ok: the {check} check fails on the mutant: {problems[check]}")
    for check in passed:
        if problems[check]:
            fail(f"the mutant should pass the {check} check: {problems[check]}")


def mutant_character_frozen():
    # The cape walks on without the frozen character: by t = 1 s it is ahead of it, not behind.
    cape_mutant("cape-frozen", "const pose = colliderPose(run, index, i);",
                "const pose = colliderPose(run, 0, i);", ["motion", "cape"], ["character"])


def mutant_draws_no_cape():
    cape_mutant("cape-undrawn", "run.scene.add(run.mesh);", "", ["cape"], ["character", "motion"])


def cloth_drawn_and_moving():
    out = os.path.join(WORK, "single")
    shutil.rmtree(out, ignore_errors=True)
    folder = frames(out, "rk4")
    page = run(CLOTHLAB, "view", folder, "--out", os.path.join(out, "view")).stdout
    page = page.split("file://", 1)[1].split()[0]
    view = (0, 0, WIDTH - PANEL, HEIGHT)
    early, late = screenshots(page, [("t=0&paused=1", os.path.join(out, "t0.png")),
                                     ("t=0.8&paused=1", os.path.join(out, "t0.8.png"))])
    check_cloth(early, view, "t = 0")
    check_cloth(late, view, "t = 0.8")
    changed = sum(1 for p in differing(early.crop(view), late.crop(view)).getdata() if p)
    if changed < 0.01 * (view[2] * view[3]):
        fail(f"only {changed} view pixels differ between t = 0 and t = 0.8: the cloth did not move")
    print(f"ok: {changed} view pixels changed between t = 0 and t = 0.8 s")


def mesh_drawn():
    out = os.path.join(WORK, "mesh")
    shutil.rmtree(out, ignore_errors=True)
    folder = os.path.join(out, "disc")
    disc = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "assets",
                        "meshes", "disc.obj")
    run(CLOTHLAB, "--plugin-path", PLUGIN_DIR, "--integrator", "xpbd", "--scenario", "mesh",
        "--set", f"scenario.file={disc}", "--set", "scenario.pin.by_box=true",
        "--set", "scenario.pin.box.min=[-0.05, 0.95, -0.05]",
        "--set", "scenario.pin.box.max=[0.05, 1.05, 0.05]", "--frame-rate", "1000",
        "--substeps", "40", "--duration", "1",
        "--set", "frames.rate=30",
        "--frames", folder, "--quiet")
    page = run(CLOTHLAB, "view", folder, "--out", os.path.join(out, "view")).stdout
    page = page.split("file://", 1)[1].split()[0]
    image = screenshot(page, "t=0.5&paused=1", os.path.join(out, "mesh.png"))
    # The disc hangs in folds from its centre: a narrower drawing than a sheet's.
    check_cloth(image, (0, 0, WIDTH - PANEL, HEIGHT), "disc mesh", least_share=0.01)
    print("ok: the mesh is drawn")


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
    mutate_page(view, "renderer.render(run.scene, camera);", "")
    image = screenshot(os.path.join(view, "index.html"), "t=0.5&paused=1",
                       os.path.join(out, "nothing-drawn.png"))
    _, count = cloth_pixels(image, (0, 0, WIDTH - PANEL, HEIGHT))
    area = (WIDTH - PANEL) * HEIGHT
    if count >= 0.03 * area:
        fail(f"a page that draws no cloth passes the cloth check ({count} of {area} pixels)")
    print(f"ok: the page without its render call shows {count} of {area} non-background pixels")


# A frames folder whose name is markup that runs a script when parsed as HTML: the script
# would mark the page's body.
INJECTED = 'run<img src=x onerror="document.body.setAttribute(\'data-injected\',\'yes\')">'


def injection_problems(view):
    """Whether the page ran the folder name's script, and whether the name reached the page at
    all (shown as text), from the page's document after its scripts ran."""
    dom = chromium_output(page_dom_start(os.path.join(view, "index.html"), "t=0&paused=1", view))
    ran = re.search(r"<body[^>]*data-injected", dom) is not None
    shown = html.escape(INJECTED, quote=False) in dom
    return ran, shown


def injected_view(out):
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    folder = os.path.join(out, INJECTED)
    run(CLOTHLAB, "--plugin-path", PLUGIN_DIR, "--integrator", "rk4", "--scenario", "flag",
        "--set", "scenario.rows=8", "--set", "scenario.cols=8", "--duration", "0.1",
        "--set", "frames.rate=30", "--frames", folder, "--quiet")
    view = os.path.join(out, "view")
    run(CLOTHLAB, "view", folder, "--out", view)
    return view


def folder_name_is_text():
    ran, shown = injection_problems(injected_view(os.path.join(WORK, "injected")))
    if ran:
        fail("the frames folder's name ran as a script in the page")
    if not shown:
        fail("the frames folder's name is not shown in the page as text")
    print("ok: the folder name is shown as text and its script did not run")


def mutant_name_as_markup():
    view = injected_view(os.path.join(WORK, "injected-mutant"))
    mutate_page(view, 'element("div", "", run.name)',
                'Object.assign(element("div"), { innerHTML: run.name })')
    ran, _ = injection_problems(view)
    if not ran:
        fail("a page that inserts the folder name as markup passes the injection check")
    print("ok: the page that inserts the folder name as markup runs its script and is caught")


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
 "mesh-drawn": mesh_drawn,
 "no-frames": no_frames, "mutant-draws-nothing": mutant_draws_nothing,
 "collider-drawn": collider_drawn, "mutant-draws-no-collider": mutant_draws_no_collider,
 "cape-frames": cape_frames, "cape-and-character": cape_and_character,
 "mutant-character-frozen": mutant_character_frozen,
 "mutant-draws-no-cape": mutant_draws_no_cape, "folder-name-is-text": folder_name_is_text,
 "mutant-name-as-markup": mutant_name_as_markup}[CASE]()
