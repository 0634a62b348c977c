// The viewer's starting camera (host/viewer/framing.js): it looks along the normal of the
// cloth's mean plane and fits the scene's box. Run by CTest with Node.
"use strict";
const assert = require("node:assert/strict");
const framing = require(process.argv[2]);

// A rows x cols grid of points spanning `first` and `second` (3-vectors) from `origin`, with a
// ripple of `bump` along their normal so the plane is a fit, not exact.
function sheet(origin, first, second, rows, cols, bump = 0) {
  const normal = [first[1] * second[2] - first[2] * second[1], first[2] * second[0] - first[0] * second[2],
                  first[0] * second[1] - first[1] * second[0]];
  const length = Math.hypot(...normal);
  const points = [];
  for (let r = 0; r < rows; ++r)
    for (let c = 0; c < cols; ++c) {
      const u = c / (cols - 1), v = r / (rows - 1), h = bump * Math.sin(7 * u + 3 * v);
      for (let i = 0; i < 3; ++i)
        points.push(origin[i] + u * first[i] + v * second[i] + (h * normal[i]) / length);
    }
  return new Float32Array(points);
}

function near(actual, expected, tolerance, what) {
  assert.ok(Math.abs(actual - expected) <= tolerance,
            `${what}: ${actual} is not within ${tolerance} of ${expected}`);
}

// The orbit's direction for an orbit computed from the frames.
function viewFrom(frames) {
  const orbit = framing.orbitAlong(framing.meanPlaneNormal(frames));
  return { orbit, direction: framing.orbitDirection(orbit.azimuth, orbit.elevation) };
}

const tests = {
  "a flat cloth in the x-y plane is seen along z": () => {
    const { orbit, direction } = viewFrom([sheet([0, 1, 0], [1, 0, 0], [0, -1, 0], 32, 32, 0.01)]);
    near(Math.abs(direction[2]), 1, 1e-3, "|z| of the view direction");
    near(orbit.elevation, 0, 1e-3, "elevation");
    assert.ok(direction[2] > 0, "the camera is on the +z side, the earlier default's side");
  },
  "a cloth in the y-z plane is seen along x": () => {
    const { direction } = viewFrom([sheet([0, 0, 0], [0, 0, 2], [0, 1, 0], 20, 40)]);
    near(direction[0], 1, 1e-6, "x of the view direction");
  },
  "a cloth tilted 45 degrees is seen from its normal's azimuth, its elevation limited": () => {
    // Spanned by (1, 0, 0) and (0, 1, 1)/sqrt 2: normal (0, -1, 1)/sqrt 2, seen from the +z side.
    const s = Math.SQRT1_2;
    const { direction } = viewFrom([sheet([0, 0, 0], [1, 0, 0], [0, s, s], 30, 30, 0.005)]);
    assert.ok(framing.MAX_ELEVATION < Math.PI / 4);
    near(direction[0], 0, 5e-3, "x");
    near(Math.atan2(-direction[1], Math.hypot(direction[0], direction[2])), framing.MAX_ELEVATION,
         1e-9, "the elevation, clamped");
  },
  "a level cloth is seen from above at the limited elevation": () => {
    const { orbit } = viewFrom([sheet([0, 0, 0], [1, 0, 0], [0, 0, 1], 25, 25, 0.01)]);
    near(orbit.elevation, framing.MAX_ELEVATION, 1e-9, "elevation");
  },
  "every frame counts: a cloth carried along its normal is seen from the side": () => {
    // A 0.5 x 0.8 cape in the y-z plane carried 2 m along x over the frames: the frames vary
    // least along z.
    const frames = [];
    for (let k = 0; k < 30; ++k)
      frames.push(sheet([(2 * k) / 29, 1.4, -0.25], [0, 0, 0.5], [0, -0.8, 0], 16, 10));
    near(Math.abs(viewFrom(frames).direction[2]), 1, 1e-3, "|z| of the view direction");
  },
  "the fitted distance keeps every corner of the box in view": () => {
    const min = [-1, -0.5, -0.2], max = [3, 1.5, 0.2];
    for (const aspect of [0.5, 1, 2.4])
      for (const orbit of [{ azimuth: 0, elevation: 0 }, { azimuth: 0.9, elevation: 0.4 }]) {
        const fovY = (40 * Math.PI) / 180;
        const distance = framing.fitDistance(min, max, orbit, fovY, aspect, 1);
        const w = framing.orbitDirection(orbit.azimuth, orbit.elevation);
        const right = [w[2], 0, -w[0]].map((c) => c / Math.hypot(w[0], w[2]));
        const up = [w[1] * right[2], w[2] * right[0] - w[0] * right[2], -w[1] * right[0]];
        let widest = 0;
        for (let corner = 0; corner < 8; ++corner) {
          const p = [0, 1, 2].map((i) => ((corner >> i) & 1 ? max[i] - min[i] : min[i] - max[i]) / 2);
          const depth = distance - (p[0] * w[0] + p[1] * w[1] + p[2] * w[2]);
          const x = Math.abs(p[0] * right[0] + p[2] * right[2]) / (depth * Math.tan(fovY / 2) * aspect);
          const y = Math.abs(p[0] * up[0] + p[1] * up[1] + p[2] * up[2]) / (depth * Math.tan(fovY / 2));
          widest = Math.max(widest, x, y);
        }
        // Every corner inside the view, and the widest one at its edge: fitted, not just far.
        near(widest, 1, 1e-9, `the outermost corner at aspect ${aspect}, azimuth ${orbit.azimuth}`);
      }
  },
};

let failed = 0;
for (const [name, test] of Object.entries(tests)) {
  try {
    test();
    console.log("ok:", name);
  } catch (error) {
    failed += 1;
    console.log("FAIL:", name, "-", error.message);
  }
}
process.exit(failed ? 1 : 0);
