#!/usr/bin/python3
"""End-to-end checks of `clothlab --frames`, read back with independent readers.

  frames_test.py CLOTHLAB PLUGIN_DIR WORK_DIR CASE
  CASE: vtk-readback   100x100 flag: VTK's own XML reader (python3-vtk9) reads every .vtp
                       listed in the .pvd; point and triangle counts, frame times, the last
                       frame against --state-out, the OBJ and PC2 files against the .vtp
        sigint         Ctrl-C in the middle of a run: exit 130, the index lists exactly the
                       frames on disk and every one of them reads back whole; an earlier
                       run's frame in the folder is gone, a file of the user's stays
        memory         peak memory of a run with 10x more frames grows by less than 5 frames
                       data (allocator noise is ~2 frames; keeping them all would be 180)
        bad-folder     an unwritable frames folder: one line naming it, exit 1, no steps run
"""
import csv
import os
import shutil
import signal
import struct
import subprocess
import sys
import time
import xml.etree.ElementTree as ElementTree

CLOTHLAB, PLUGIN_DIR, WORK, CASE = sys.argv[1:5]


def fail(message):
    print("FAIL:", message)
    sys.exit(1)


def check(condition, message):
    if not condition:
        fail(message)


def clothlab_command(frames_dir, *arguments):
    return [CLOTHLAB, "--plugin-path", PLUGIN_DIR, "--frames", frames_dir, *arguments]


def fresh(name):
    path = os.path.join(WORK, name)
    shutil.rmtree(path, ignore_errors=True)
    os.makedirs(path)
    return path


def pvd_entries(path):
    root = ElementTree.parse(path).getroot()
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]


def read_vtp(path):
    import vtk
    from vtk.util.numpy_support import vtk_to_numpy
    reader = vtk.vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    data = reader.GetOutput()
    check(reader.GetErrorCode() == 0 and data.GetNumberOfPoints() > 0, f"VTK cannot read {path}")
    return data, vtk_to_numpy


def vtk_readback():
    import numpy
    out = fresh("vtk-readback")
    frames, state = os.path.join(out, "frames"), os.path.join(out, "state.csv")
    n, dt, duration, every = 100, 0.0005, 0.2, 40
    run = subprocess.run(clothlab_command(
        frames, "--integrator", "rk4", "--scenario", "flag", "--set", f"scenario.rows={n}",
        "--set", f"scenario.cols={n}", "--dt", str(dt), "--duration", str(duration),
        "--set", f"frames.every={every}", "--set", "frames.format=[vtp, obj, pc2]",
        "--state-out", state, "--quiet"), capture_output=True, text=True)
    check(run.returncode == 0, f"run failed ({run.returncode}): {run.stderr}")
    steps = round(duration / dt)
    entries = pvd_entries(os.path.join(frames, "frames.pvd"))
    expected_steps = list(range(0, steps + 1, every))
    check([round(t / dt) for t, _ in entries] == expected_steps,
          f"frame times {[t for t, _ in entries]} are not every {every} steps of {dt} s")
    for t, name in entries:
        data, to_numpy = read_vtp(os.path.join(frames, name))
        check(data.GetNumberOfPoints() == n * n, f"{name}: {data.GetNumberOfPoints()} points")
        check(data.GetNumberOfStrips() == n - 1, f"{name}: {data.GetNumberOfStrips()} strips")
        time_value = to_numpy(data.GetFieldData().GetArray("TimeValue"))[0]
        check(abs(time_value - t) < 1e-12, f"{name}: TimeValue {time_value}, index says {t}")
        for field, components in (("velocity", 3), ("stretch", 1)):
            array = data.GetPointData().GetArray(field)
            check(array is not None and array.GetNumberOfComponents() == components
                  and array.GetNumberOfTuples() == n * n, f"{name}: point data {field}")
        stretch = to_numpy(data.GetPointData().GetArray("stretch"))
        check(stretch.min() > 0.5 and stretch.max() < 5, f"{name}: stretch {stretch.min()}..{stretch.max()}")
    with open(state) as stream:
        final = numpy.array([[float(r["x"]), float(r["y"]), float(r["z"])] for r in csv.DictReader(stream)])
    last, to_numpy = read_vtp(os.path.join(frames, entries[-1][1]))
    points = to_numpy(last.GetPoints().GetData()).astype(float)
    error = numpy.abs(points - final).max()
    check(error < 1e-6, f"last frame differs from --state-out by {error} m")
    first, _ = read_vtp(os.path.join(frames, entries[0][1]))
    moved = numpy.abs(to_numpy(first.GetPoints().GetData()) - points).max()
    check(moved > 1e-3, f"the cloth did not move between the first and last frame ({moved} m)")

    with open(os.path.join(frames, "frames.pc2"), "rb") as stream:
        cache = stream.read()
    magic, version, count, start, rate, samples = struct.unpack("<12siiffi", cache[:32])
    check(magic == b"POINTCACHE2\0" and version == 1 and count == n * n and samples == len(entries),
          f"PC2 header {magic, version, count, samples}")
    check(len(cache) == 32 + samples * count * 12, f"PC2 holds {len(cache)} bytes")
    cached_last = numpy.frombuffer(cache[-count * 12:], dtype="<f4").reshape(-1, 3)
    check(numpy.array_equal(cached_last, points.astype("f4")), "PC2's last sample differs from the .vtp")
    with open(os.path.join(frames, entries[-1][1].replace(".vtp", ".obj"))) as stream:
        lines = stream.read().splitlines()
    vertices = numpy.array([[float(v) for v in line.split()[1:]] for line in lines if line.startswith("v ")])
    faces = [line for line in lines if line.startswith("f ")]
    check(vertices.shape == (n * n, 3) and len(faces) == 2 * (n - 1) ** 2, "OBJ counts")
    # VTK's own decomposition of the strips: the OBJ's triangles, each turned the same way.
    import vtk
    triangulate = vtk.vtkTriangleFilter()
    triangulate.SetInputData(last)
    triangulate.Update()
    polys = to_numpy(triangulate.GetOutput().GetPolys().GetConnectivityArray()).reshape(-1, 3)

    def turned_to_least_first(triangles):
        return {tuple(t[t.index(min(t)):] + t[:t.index(min(t))]) for t in map(list, triangles)}

    obj_triangles = [[int(v) - 1 for v in face.split()[1:]] for face in faces]
    check(len(polys) == 2 * (n - 1) ** 2
          and turned_to_least_first(polys.tolist()) == turned_to_least_first(obj_triangles),
          f"the .vtp's strips ({len(polys)} triangles) are not the OBJ's triangles")
    check(numpy.abs(vertices - points).max() < 1e-6, "OBJ positions differ from the .vtp")
    print(f"ok: {len(entries)} frames, {n * n} points, {2 * (n - 1) ** 2} triangles; "
          f"last frame vs --state-out {error:.2e} m")


def sigint():
    import vtk  # noqa: F401  (fail early if missing)
    out = fresh("sigint")
    frames = os.path.join(out, "frames")
    # An earlier run's frame goes (the folder shows one run); a file of the user's stays.
    os.makedirs(frames)
    for planted in ("frame_000999.vtp", "notes.txt"):
        open(os.path.join(frames, planted), "w").close()
    process = subprocess.Popen(clothlab_command(
        frames, "--integrator", "rk4", "--scenario", "flag", "--set", "scenario.rows=60",
        "--set", "scenario.cols=60", "--dt", "0.0005", "--duration", "1000",
        "--set", "frames.every=20", "--set", "frames.format=[vtp, pc2]", "--json",
        os.path.join(out, "run.json"), "--quiet"), stderr=subprocess.PIPE, text=True)
    deadline = time.time() + 60
    while not os.path.exists(os.path.join(frames, "frame_000005.vtp")):
        check(time.time() < deadline and process.poll() is None, "no frames within 60 s")
        time.sleep(0.05)
    process.send_signal(signal.SIGINT)
    _, stderr = process.communicate(timeout=60)
    check(process.returncode == 130, f"exit code {process.returncode}: {stderr}")
    check("interrupted" in stderr and stderr.count("\n") == 1, f"stderr: {stderr!r}")
    entries = pvd_entries(os.path.join(frames, "frames.pvd"))
    on_disk = sorted(f for f in os.listdir(frames) if f.endswith(".vtp"))
    check(sorted(name for _, name in entries) == on_disk, f"index {entries} vs files {on_disk}")
    check(not [f for f in os.listdir(frames) if f.startswith(".")], "temporary files left")
    check(os.path.exists(os.path.join(frames, "notes.txt")), "notes.txt was removed")
    for _, name in entries:
        data, _ = read_vtp(os.path.join(frames, name))
        check(data.GetNumberOfPoints() == 3600, f"{name} is incomplete")
    with open(os.path.join(frames, "frames.pc2"), "rb") as stream:
        samples = struct.unpack("<i", stream.read(32)[28:32])[0]
    check(samples == len(entries), f"PC2 has {samples} samples, the index {len(entries)}")
    import json
    with open(os.path.join(frames, "run.json")) as stream:
        run = json.load(stream)
    check(run["status"] == "finished" and run["summary"]["interrupted"], "run.json: not finished")
    print(f"ok: interrupted after {len(entries)} frames, index and files agree")


def peak_memory_kib(*arguments):
    process = subprocess.Popen(arguments, stdout=subprocess.DEVNULL)
    _, status, usage = os.wait4(process.pid, 0)
    check(os.waitstatus_to_exitcode(status) == 0, f"{arguments} failed")
    return usage.ru_maxrss


def memory():
    out = fresh("memory")
    n = 200
    frame_kib = n * n * 4 * 7 / 1024  # positions, velocities, stretch in float32
    peaks = {}
    for frames in (20, 200):
        peaks[frames] = peak_memory_kib(*clothlab_command(
            os.path.join(out, f"frames-{frames}"), "--integrator", "euler", "--scenario", "sheet",
            "--set", f"scenario.rows={n}", "--set", f"scenario.cols={n}", "--dt", "0.0001",
            "--steps", str(frames * 2), "--set", "frames.every=2", "--quiet"))
    growth = peaks[200] - peaks[20]
    check(growth < 5 * frame_kib, f"peak memory grew by {growth} KiB from 20 to 200 frames "
                              f"(one frame is {frame_kib:.0f} KiB): {peaks}")
    print(f"ok: peak memory {peaks} KiB (20 vs 200 frames), growth {growth} KiB")


def bad_folder():
    out = fresh("bad-folder")
    blocker = os.path.join(out, "a-file")
    open(blocker, "w").close()
    run = subprocess.run(clothlab_command(os.path.join(blocker, "frames"), "--scenario", "sheet",
                                          "--steps", "10"), capture_output=True, text=True)
    check(run.returncode == 1, f"exit code {run.returncode}")
    check(run.stdout == "", f"the run started: {run.stdout!r}")
    lines = run.stderr.splitlines()
    check(len(lines) == 1 and "a-file/frames" in lines[0], f"stderr: {run.stderr!r}")
    print("ok:", lines[0])


{"vtk-readback": vtk_readback, "sigint": sigint, "memory": memory,
 "bad-folder": bad_folder}[CASE]()
