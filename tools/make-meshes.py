#!/usr/bin/env python3
"""Writes the meshes ClothLab ships under assets/meshes/ (OBJ): run from anywhere,
   python3 tools/make-meshes.py
and commit the output. Every coordinate is y up, metres; every mesh is one consistently wound
surface (the mesh scenario checks it when it reads the file).

  curtain.obj        1.2 m x 1.5 m of quads hanging from y = 2, with a hem: the bottom 4 cm
                     turned up behind the curtain in rows 1 cm apart (the body's are 5 cm)
  disc.obj           a 0.5 m radius disc at y = 1 of triangles in rings, each ring 6 more
                     vertices than the one inside it and turned against it (irregular)
  cape.obj           the cape scenario's cape cut as a trapezoid: its top edge on the cape's
                     attachment line behind the character's shoulders (x = -0.19, y = 1.42,
                     0.5 m across z), flaring to 0.7 m across at 0.8 m below
  tshirt.obj         a T-shirt-like tube: a body that narrows from the hem to the shoulders,
                     open at the neck and the hem (no sleeves)
  flag-30-quads.obj, flag-30-triangles.obj, sheet-30-quads.obj, sheet-30-triangles.obj
                     the flag and sheet scenarios' 30 x 30 grids at 0.90625 m sides (spacing
                     1/32 m, exact in the float Assimp reads coordinates into), as quads and as
                     the grid's own triangles (core/src/grid_triangles.cpp); vertex (r, c) is the
                     grid's particle r * 30 + c, written in that order; the sheet's two
                     pinned corners are coloured red, the rest white (pin.by_color)
"""
import pathlib

import numpy as np

OUT = pathlib.Path(__file__).resolve().parent.parent / "assets" / "meshes"


def write_obj(name, vertices, faces, comment, colours=None):
    """colours: one RGB per vertex, written as OBJ's "v x y z r g b" (Assimp reads them)."""
    lines = [f"# {line}" for line in comment.strip().splitlines()]
    lines.append("# written by tools/make-meshes.py; y up, metres")
    for i, v in enumerate(vertices):
        values = list(v) + (list(colours[i]) if colours else [])
        lines.append("v " + " ".join(repr(float(x)) for x in values))
    lines += ["f " + " ".join(str(i + 1) for i in face) for face in faces]
    (OUT / name).write_text("\n".join(lines) + "\n")
    check_winding(name, vertices, faces)


def check_winding(name, vertices, faces):
    """Every edge in at most two faces, the two in opposite directions."""
    seen = set()
    for face in faces:
        for a, b in zip(face, face[1:] + face[:1]):
            if (a, b) in seen:
                raise SystemExit(f"{name}: edge {a}-{b} wound twice the same way")
            seen.add((a, b))


def grid_faces(rows, cols, offset=0, quads=True):
    """Quads (r, c), (r, c+1), (r+1, c+1), (r+1, c) of a row-major grid (wound as the grid's
    triangles), or the grid's triangles."""
    faces = []
    for c in range(cols - 1):
        for r in range(rows - 1):
            a = offset + r * cols + c
            b, below = a + 1, a + cols
            if quads:
                faces.append([a, b, below + 1, below])
            else:
                faces += [[a, b, below], [b, below + 1, below]]
    return faces


def curtain():
    cols, width, top = 25, 1.2, 2.0
    body = np.arange(top, 0.54 - 1e-9, -0.05)  # 2.0 .. 0.55 by 5 cm
    hem_front = np.array([0.54, 0.53, 0.52, 0.51, 0.50])
    hem_back = np.array([0.51, 0.52, 0.53, 0.54])
    rows = [(y, 0.0) for y in body] + [(y, 0.0) for y in hem_front] + [(y, -0.006) for y in hem_back]
    xs = np.linspace(-width / 2, width / 2, cols)
    vertices = [(x, y, z) for (y, z) in rows for x in xs]
    write_obj("curtain.obj", vertices, grid_faces(len(rows), cols),
              "Curtain with a hem: pin its top edge (pin.by_box, y >= 1.999).")


def ring_faces(inner, inner_angles, outer, outer_angles):
    """Triangles between two rings, marching by angle (both sorted, starting close together)."""
    faces, i, j = [], 0, 0
    n, m = len(inner), len(outer)
    while i < n or j < m:
        next_in = inner_angles[(i + 1) % n] + (2 * np.pi if i + 1 >= n else 0)
        next_out = outer_angles[(j + 1) % m] + (2 * np.pi if j + 1 >= m else 0)
        if j < m and (i >= n or next_out <= next_in):
            faces.append([inner[i % n], outer[j], outer[(j + 1) % m]])
            j += 1
        else:
            faces.append([inner[i % n], outer[j % m], inner[(i + 1) % n]])
            i += 1
    return faces


def disc():
    radius, rings, height = 0.5, 16, 1.0
    vertices, faces = [(0.0, height, 0.0)], []
    previous, previous_angles = None, None
    for k in range(1, rings + 1):
        count = 6 * k
        turn = 0.3 * (k % 2) * 2 * np.pi / count  # alternate rings turned: no straight spokes
        angles = turn + 2 * np.pi * np.arange(count) / count
        r = radius * k / rings
        start = len(vertices)
        # Angles run from +x towards -z, so that the faces' normals point up (+y).
        vertices += [(r * np.cos(a), height, -r * np.sin(a)) for a in angles]
        ring = list(range(start, start + count))
        if previous is None:
            faces += [[0, ring[j], ring[(j + 1) % count]] for j in range(count)]
        else:
            faces += ring_faces(previous, previous_angles, ring, angles)
        previous, previous_angles = ring, angles
    write_obj("disc.obj", vertices, faces,
              "Disc of triangle rings: pin its centre (pin.by_box around (0, 1, 0)).")


def cape():
    rows, cols, top, length, back = 32, 20, 1.42, 0.8, -0.19
    vertices = []
    for r in range(rows):
        t = r / (rows - 1)
        half = 0.25 + t * (0.35 - 0.25)
        vertices += [(back, top - t * length, z) for z in np.linspace(-half, half, cols)]
    # Quads split along alternating diagonals: a cut cloth's triangles, not the grid's.
    faces = []
    for r in range(rows - 1):
        for c in range(cols - 1):
            a = r * cols + c
            b, below = a + 1, a + cols
            if (r + c) % 2 == 0:
                faces += [[a, below, below + 1], [a, below + 1, b]]
            else:
                faces += [[a, below, b], [b, below, below + 1]]
    write_obj("cape.obj", vertices, faces,
              "Cape on the cape scenario's shoulder line: pin its top edge (pin.by_box, y >= 1.419).")


def tshirt():
    around, rows, hem, shoulders = 40, 30, 0.7, 1.35
    vertices = []
    for r in range(rows):
        t = r / (rows - 1)
        y = shoulders - t * (shoulders - hem)
        # Narrow at the neck, widest at the chest, a little narrower at the waist and hem.
        rx = 0.10 + 0.12 * np.sin(np.pi * min(1.0, 3 * t) / 2) - 0.02 * t
        rz = 0.07 + 0.05 * np.sin(np.pi * min(1.0, 3 * t) / 2)
        angles = 2 * np.pi * np.arange(around) / around
        vertices += [(rx * np.cos(a), y, -rz * np.sin(a)) for a in angles]
    faces = []
    for r in range(rows - 1):
        for c in range(around):
            a, b = r * around + c, r * around + (c + 1) % around
            faces.append([a, a + around, b + around, b])
    write_obj("tshirt.obj", vertices, faces,
              "T-shirt-like tube: pin its neck ring (pin.by_plane through y = 1.35, normal +y).")


def grid(name, origin, quads, pinned_corners):
    """pinned_corners: colour the top-left and top-right vertices red and the rest white, for
    the sheet's two pins (pin.by_color)."""
    rows = cols = 30
    spacing = 1.0 / 32.0
    vertices = [(origin[0] + c * spacing, origin[1] - r * spacing, 0.0)
                for r in range(rows) for c in range(cols)]
    colours = None
    if pinned_corners:
        colours = [(1, 1, 1)] * (rows * cols)
        colours[0] = colours[cols - 1] = (1, 0, 0)
    write_obj(f"{name}-30-{'quads' if quads else 'triangles'}.obj", vertices,
              grid_faces(rows, cols, quads=quads),
              f"The {name} scenario's 30 x 30 grid, 0.90625 m sides (width = height = 0.90625).",
              colours)


def main():
    OUT.mkdir(parents=True, exist_ok=True)
    curtain()
    disc()
    cape()
    tshirt()
    side = 29.0 / 32.0
    for quads in (True, False):
        grid("flag", (0.0, side), quads, pinned_corners=False)
        grid("sheet", (-side / 2, side), quads, pinned_corners=True)


if __name__ == "__main__":
    main()
