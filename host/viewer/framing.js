// Where the viewer's camera starts: looking along the normal of the cloth's mean plane, so the
// cloth's two largest extents face the camera, at the distance that fits the scene's bounding
// box. Plain functions of arrays, loaded by the page before viewer.js and by Node in the tests.
"use strict";

const ClothLabFraming = (() => {
  // The starting orbit of earlier pages, kept as the side to look from when the plane gives no
  // preference (a normal is a direction up to its sign; a level cloth has no azimuth).
  const DEFAULT_AZIMUTH = 0.6, DEFAULT_ELEVATION = 0.3;
  // A level cloth is seen from this high (radians) rather than from straight above, so what
  // lies under it (a collider it drapes over) stays in view.
  const MAX_ELEVATION = 0.7;
  // Below this horizontal part of the normal the cloth counts as level: its azimuth would be
  // decided by noise.
  const LEVEL = 0.2;

  // The direction from the orbit's centre to the camera at (azimuth, elevation).
  function orbitDirection(azimuth, elevation) {
    return [Math.cos(elevation) * Math.sin(azimuth), Math.sin(elevation),
            Math.cos(elevation) * Math.cos(azimuth)];
  }

  // The eigenvector of a symmetric 3x3 matrix (rows as arrays) with the smallest eigenvalue, by
  // cyclic Jacobi rotations.
  function smallestEigenvector(matrix) {
    const a = matrix.map((row) => row.slice());
    const v = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];
    for (let sweep = 0; sweep < 50; ++sweep) {
      const off = a[0][1] ** 2 + a[0][2] ** 2 + a[1][2] ** 2;
      if (off <= 1e-30 * (a[0][0] ** 2 + a[1][1] ** 2 + a[2][2] ** 2) || off === 0) break;
      for (const [p, q] of [[0, 1], [0, 2], [1, 2]]) {
        if (a[p][q] === 0) continue;
        const theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
        const t = Math.sign(theta || 1) / (Math.abs(theta) + Math.sqrt(theta * theta + 1));
        const c = 1 / Math.sqrt(t * t + 1), s = t * c;
        for (let k = 0; k < 3; ++k) {  // a = J^T a J, column then row
          const akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (let k = 0; k < 3; ++k) {
          const apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (let k = 0; k < 3; ++k) {
          const vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
    }
    let smallest = 0;
    for (let k = 1; k < 3; ++k) if (a[k][k] < a[smallest][smallest]) smallest = k;
    return [v[0][smallest], v[1][smallest], v[2][smallest]];
  }

  // The unit normal of the least-squares plane through the points of every frame (flat arrays
  // x, y, z, x, ...): the axis along which they vary least. Taking every frame, not the first,
  // frames the cloth where it goes (a flag that swings round its pole, a cape carried along).
  function meanPlaneNormal(frames) {
    let count = 0;
    const mean = [0, 0, 0];
    for (const frame of frames)
      for (let k = 0; k + 2 < frame.length; k += 3, ++count)
        for (let i = 0; i < 3; ++i) mean[i] += frame[k + i];
    if (count === 0) return orbitDirection(DEFAULT_AZIMUTH, DEFAULT_ELEVATION);
    for (let i = 0; i < 3; ++i) mean[i] /= count;
    const covariance = [[0, 0, 0], [0, 0, 0], [0, 0, 0]];
    for (const frame of frames)
      for (let k = 0; k + 2 < frame.length; k += 3) {
        const d = [frame[k] - mean[0], frame[k + 1] - mean[1], frame[k + 2] - mean[2]];
        for (let i = 0; i < 3; ++i)
          for (let j = 0; j < 3; ++j) covariance[i][j] += d[i] * d[j];
      }
    return smallestEigenvector(covariance);
  }

  // The orbit (azimuth, elevation) that looks along `normal`, from the side of the earlier
  // default viewpoint, with a level cloth seen from MAX_ELEVATION above.
  function orbitAlong(normal) {
    const preferred = orbitDirection(DEFAULT_AZIMUTH, DEFAULT_ELEVATION);
    const facing = normal[0] * preferred[0] + normal[1] * preferred[1] + normal[2] * preferred[2];
    const n = facing < 0 ? normal.map((c) => -c) : normal;
    const horizontal = Math.hypot(n[0], n[2]);
    const elevation = Math.max(-MAX_ELEVATION,
                               Math.min(MAX_ELEVATION, Math.atan2(n[1], horizontal)));
    const azimuth = horizontal < LEVEL ? DEFAULT_AZIMUTH : Math.atan2(n[0], n[2]);
    return { azimuth, elevation };
  }

  // The camera distance from the box's centre at which every corner of the box (its min and max
  // corners) lies inside a perspective view along the orbit, with vertical field of view fovY
  // (radians) and aspect width / height, and a margin around it.
  function fitDistance(min, max, orbit, fovY, aspect, margin = 1.08) {
    const w = orbitDirection(orbit.azimuth, orbit.elevation);  // towards the camera
    const right = [w[2], 0, -w[0]];  // the camera's right: forward (-w) x up (+y), normalised
    const length = Math.hypot(right[0], right[2]) || 1;
    right[0] /= length; right[2] /= length;
    const up = [w[1] * right[2] - w[2] * right[1], w[2] * right[0] - w[0] * right[2],
                w[0] * right[1] - w[1] * right[0]];
    const tanY = Math.tan(fovY / 2), tanX = tanY * aspect;
    const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
    let distance = 0;
    for (let corner = 0; corner < 8; ++corner) {
      const p = [0, 1, 2].map((i) => ((corner >> i) & 1 ? max[i] - min[i] : min[i] - max[i]) / 2);
      const depth = dot(p, w);  // nearer the camera by this much
      distance = Math.max(distance, depth + Math.abs(dot(p, right)) / tanX,
                          depth + Math.abs(dot(p, up)) / tanY);
    }
    return margin * distance;
  }

  return { orbitDirection, meanPlaneNormal, orbitAlong, fitDistance, MAX_ELEVATION };
})();

if (typeof module !== "undefined") module.exports = ClothLabFraming;
