// multibody-view: plays a sampled multibody motion with WebGL2 and plots
// signals beside it. Everything it needs is in this page: the scene (shapes,
// frame poses over time, signals) is the JSON in #mb-scene, with the arrays
// as base64 little-endian Float32.
//
// Conventions: world y is up. A pose is a position and the unit quaternion
// [w, x, y, z] of the frame-to-world rotation.
//
// Query parameters (for tests and links): t=SECONDS shows that time, paused;
// panel=0 shows the 3-D view alone; bench=N times N frames and logs it.
"use strict";
(function () {
  var report = window.__multibodyReport || function (m) { console.log("multibody-view error: " + m); };
  var scene = JSON.parse(document.getElementById("mb-scene").textContent);
  var query = new URLSearchParams(window.location.search);

  // The bytes of a base64 string, as an ArrayBuffer.
  function buffer(b64) {
    var s = atob(b64 || "");
    var bytes = new Uint8Array(s.length);
    for (var i = 0; i < s.length; i++) bytes[i] = s.charCodeAt(i);
    return bytes.buffer;
  }
  function floats(b64) { return new Float32Array(buffer(b64)); }
  function uints(b64) { return new Uint32Array(buffer(b64)); }

  // The motion; a live page replaces it after each run (setScene).
  var times, frameCount, poseCount, vectorCount, poses, vectorData, tStart, tEnd;
  function readMotion() {
    times = floats(scene.times);
    frameCount = times.length;
    poseCount = scene.poseCount;
    vectorCount = scene.vectorCount;
    poses = floats(scene.poses);
    vectorData = floats(scene.vectors);
    tStart = times[0];
    tEnd = times[frameCount - 1];
    posePosition = new Float64Array(poseCount * 3);
    poseRotation = new Float64Array(poseCount * 9); // row-major, frame to world
    vectorNow = new Float64Array(vectorCount * 3);
  }

  // ------------------------------------------------------------ 3-vectors
  function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
  function addScaled(a, b, s) { return [a[0] + b[0] * s, a[1] + b[1] * s, a[2] + b[2] * s]; }
  function scale(a, s) { return [a[0] * s, a[1] * s, a[2] * s]; }
  function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
  function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
  function norm(a) { return Math.sqrt(dot(a, a)); }
  function unit(a) { var n = norm(a); return n > 0 ? scale(a, 1 / n) : [1, 0, 0]; }
  // A unit vector perpendicular to the unit e, as close to `hint` as can be.
  function perpendicular(hint, e) {
    var candidates = [hint, [0, 1, 0], [1, 0, 0], [0, 0, 1]];
    for (var i = 0; i < candidates.length; i++) {
      var c = candidates[i];
      if (!c) continue;
      var u = addScaled(c, e, -dot(c, e));
      var n = norm(u);
      if (n > 1e-6 * Math.max(1, norm(c)) && n > 0.05 * norm(c)) return scale(u, 1 / n);
    }
    return unit(cross(e, [0, 0, 1]));
  }
  // Row-major 3x3 times vector.
  function apply3(m, o, v) {
    return [m[o] * v[0] + m[o + 1] * v[1] + m[o + 2] * v[2],
            m[o + 3] * v[0] + m[o + 4] * v[1] + m[o + 5] * v[2],
            m[o + 6] * v[0] + m[o + 7] * v[1] + m[o + 8] * v[2]];
  }

  // ------------------------------------------------------------ 4x4 (column-major)
  function multiply(a, b) {
    var out = new Float32Array(16);
    for (var c = 0; c < 4; c++) {
      for (var r = 0; r < 4; r++) {
        var s = 0;
        for (var k = 0; k < 4; k++) s += a[k * 4 + r] * b[c * 4 + k];
        out[c * 4 + r] = s;
      }
    }
    return out;
  }
  function perspective(fovy, aspect, near, far) {
    var f = 1 / Math.tan(fovy / 2), nf = 1 / (near - far);
    return new Float32Array([f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) * nf, -1, 0, 0, 2 * far * near * nf, 0]);
  }
  function orthographic(half, near, far) {
    var nf = 1 / (near - far);
    return new Float32Array([1 / half, 0, 0, 0, 0, 1 / half, 0, 0, 0, 0, 2 * nf, 0, 0, 0, (far + near) * nf, 1]);
  }
  // The camera's axes: x right, y up, z from the target towards the eye.
  function cameraAxes(eye, target) {
    var z = unit(sub(eye, target));
    var x = unit(cross([0, 1, 0], z));
    if (norm(cross([0, 1, 0], z)) < 1e-9) x = [1, 0, 0];
    var y = cross(z, x);
    return { x: x, y: y, z: z };
  }
  function lookAt(eye, axes) {
    var x = axes.x, y = axes.y, z = axes.z;
    return new Float32Array([x[0], y[0], z[0], 0, x[1], y[1], z[1], 0, x[2], y[2], z[2], 0,
      -dot(x, eye), -dot(y, eye), -dot(z, eye), 1]);
  }
  function transformPoint(m, p) {
    var x = m[0] * p[0] + m[4] * p[1] + m[8] * p[2] + m[12];
    var y = m[1] * p[0] + m[5] * p[1] + m[9] * p[2] + m[13];
    var w = m[3] * p[0] + m[7] * p[1] + m[11] * p[2] + m[15];
    return [x / w, y / w];
  }

  // ------------------------------------------------------------ poses at a time
  var posePosition, poseRotation, vectorNow;
  readMotion();

  function frameAt(t) {
    if (!(t > times[0])) return [0, 0, 0];
    if (t >= times[frameCount - 1]) return [frameCount - 1, frameCount - 1, 0];
    var lo = 0, hi = frameCount - 1;
    while (hi - lo > 1) {
      var mid = (lo + hi) >> 1;
      if (times[mid] <= t) lo = mid; else hi = mid;
    }
    var span = times[hi] - times[lo];
    return [lo, hi, span > 0 ? (t - times[lo]) / span : 0];
  }

  function updatePoses(t) {
    var f = frameAt(t), k0 = f[0], k1 = f[1], w = f[2];
    for (var j = 0; j < poseCount; j++) {
      var a = (k0 * poseCount + j) * 7, b = (k1 * poseCount + j) * 7;
      for (var i = 0; i < 3; i++) posePosition[j * 3 + i] = poses[a + i] * (1 - w) + poses[b + i] * w;
      var s = (poses[a + 3] * poses[b + 3] + poses[a + 4] * poses[b + 4] + poses[a + 5] * poses[b + 5] + poses[a + 6] * poses[b + 6]) < 0 ? -1 : 1;
      var qw = poses[a + 3] * (1 - w) + s * poses[b + 3] * w;
      var qx = poses[a + 4] * (1 - w) + s * poses[b + 4] * w;
      var qy = poses[a + 5] * (1 - w) + s * poses[b + 5] * w;
      var qz = poses[a + 6] * (1 - w) + s * poses[b + 6] * w;
      var n = Math.sqrt(qw * qw + qx * qx + qy * qy + qz * qz) || 1;
      qw /= n; qx /= n; qy /= n; qz /= n;
      var o = j * 9;
      poseRotation[o] = 1 - 2 * (qy * qy + qz * qz);
      poseRotation[o + 1] = 2 * (qx * qy - qw * qz);
      poseRotation[o + 2] = 2 * (qx * qz + qw * qy);
      poseRotation[o + 3] = 2 * (qx * qy + qw * qz);
      poseRotation[o + 4] = 1 - 2 * (qx * qx + qz * qz);
      poseRotation[o + 5] = 2 * (qy * qz - qw * qx);
      poseRotation[o + 6] = 2 * (qx * qz - qw * qy);
      poseRotation[o + 7] = 2 * (qy * qz + qw * qx);
      poseRotation[o + 8] = 1 - 2 * (qx * qx + qy * qy);
    }
    for (var v = 0; v < vectorCount; v++) {
      for (var c = 0; c < 3; c++) {
        vectorNow[v * 3 + c] = vectorData[(k0 * vectorCount + v) * 3 + c] * (1 - w) + vectorData[(k1 * vectorCount + v) * 3 + c] * w;
      }
    }
  }
  function positionOf(j) { return [posePosition[j * 3], posePosition[j * 3 + 1], posePosition[j * 3 + 2]]; }
  // A frame's y axis in world coordinates (the second column).
  function yAxisOf(j) { var o = j * 9; return [poseRotation[o + 1], poseRotation[o + 4], poseRotation[o + 7]]; }

  // ------------------------------------------------------------ shapes
  function makeShape(s) {
    var item = {
      kind: s.kind, color: s.color, specular: s.specular, place: s.place,
      width: s.width > 0 ? s.width : 0.01,
      height: s.height > 0 ? s.height : (s.width > 0 ? s.width : 0.01),
      windings: s.windings || 0,
      transparent: s.color[3] < 0.999,
      pose: s.pose, from: s.from, to: s.to, vector: s.vector, scale: s.scale
    };
    if (s.place === "frame") {
      var length = norm(s.length);
      var e1 = length > 1e-12 ? scale(s.length, 1 / length) : [1, 0, 0];
      var e2 = perpendicular(s.widthDir, e1);
      item.local = { origin: s.origin, length: length, e1: e1, e2: e2, e3: cross(e1, e2) };
    }
    if (item.kind === "helix" && meshes) item.mesh = helixMesh(item.windings);
    if (item.kind === "mesh") {
      // A point p of the file goes to transform * (scale * p) in the frame:
      // the 3x3 part times the scale (row-major), its normal matrix (the
      // cofactors, signed so a mirror keeps normals outward), the offset.
      var t = s.transform, k = s.scale;
      var a = [t[0] * k, t[1] * k, t[2] * k, t[4] * k, t[5] * k, t[6] * k, t[8] * k, t[9] * k, t[10] * k];
      var c = [a[4] * a[8] - a[5] * a[7], a[5] * a[6] - a[3] * a[8], a[3] * a[7] - a[4] * a[6],
               a[2] * a[7] - a[1] * a[8], a[0] * a[8] - a[2] * a[6], a[1] * a[6] - a[0] * a[7],
               a[1] * a[5] - a[2] * a[4], a[2] * a[3] - a[0] * a[5], a[0] * a[4] - a[1] * a[3]];
      var det = a[0] * c[0] + a[1] * c[1] + a[2] * c[2];
      if (det < 0) c = c.map(function (x) { return -x; });
      item.meshIndex = s.mesh;
      item.linear = a;
      item.cofactor = c;
      item.offset = [t[3], t[7], t[11]];
    }
    return item;
  }
  var meshes = null;
  var shapes = scene.shapes.map(makeShape);

  // Where a shape is now: origin, orthonormal axes (e1 along its length)
  // and length, all in world coordinates.
  function placeShape(s) {
    if (s.place === "frame") {
      var o = s.pose * 9, l = s.local;
      return {
        origin: addScaled(positionOf(s.pose), apply3(poseRotation, o, l.origin), 1),
        e1: apply3(poseRotation, o, l.e1), e2: apply3(poseRotation, o, l.e2), e3: apply3(poseRotation, o, l.e3),
        length: l.length
      };
    }
    var start, d, hint;
    if (s.place === "between") {
      start = positionOf(s.from);
      d = sub(positionOf(s.to), start);
      hint = yAxisOf(s.from);
    } else {
      start = positionOf(s.pose);
      var v = s.vector * 3;
      d = [vectorNow[v] * s.scale, vectorNow[v + 1] * s.scale, vectorNow[v + 2] * s.scale];
      hint = [0, 1, 0];
    }
    var length = norm(d);
    var e1 = length > 0 ? scale(d, 1 / length) : [1, 0, 0];
    var e2 = perpendicular(hint, e1);
    return { origin: start, e1: e1, e2: e2, e3: cross(e1, e2), length: length };
  }

  // ------------------------------------------------------------ WebGL
  var canvas = document.getElementById("mb-canvas");
  var gl = null;
  try {
    gl = canvas.getContext("webgl2", { antialias: true, preserveDrawingBuffer: true });
  } catch (e) {
    gl = null;
  }
  if (!gl) report("WebGL2 is not available in this browser: the 3-D view cannot be drawn (the plots still work)");

  var MESH_VS = [
    "#version 300 es",
    "precision highp float;",
    "layout(location = 0) in vec3 aPosition;",
    "layout(location = 1) in vec3 aNormal;",
    "uniform mat4 uViewProjection;",
    "uniform mat4 uModel;",
    "uniform mat3 uNormalMatrix;",
    // length, coil radius, wire radius, windings; length 0 for meshes.
    "uniform vec4 uHelix;",
    "out vec3 vNormal;",
    "out vec3 vWorld;",
    "void main() {",
    "  vec3 p = aPosition;",
    "  vec3 n = aNormal;",
    "  if (uHelix.x > 0.0) {",
    "    float turn = 6.28318530718 * uHelix.w;",
    "    float th = turn * aPosition.x;",
    "    vec3 c = vec3(uHelix.x * aPosition.x, uHelix.y * cos(th), uHelix.y * sin(th));",
    "    vec3 t = normalize(vec3(uHelix.x, -uHelix.y * turn * sin(th), uHelix.y * turn * cos(th)));",
    "    vec3 r = vec3(0.0, cos(th), sin(th));",
    "    vec3 b = cross(t, r);",
    "    n = cos(aPosition.y) * r + sin(aPosition.y) * b;",
    "    p = c + uHelix.z * n;",
    "  }",
    "  vec4 world = uModel * vec4(p, 1.0);",
    "  vWorld = world.xyz;",
    "  vNormal = uNormalMatrix * n;",
    "  gl_Position = uViewProjection * world;",
    "}"
  ].join("\n");

  var MESH_FS = [
    "#version 300 es",
    "precision highp float;",
    "in vec3 vNormal;",
    "in vec3 vWorld;",
    "uniform vec4 uColor;",
    "uniform float uSpecular;",
    "uniform vec3 uEye;",
    "uniform vec3 uLight;",
    "out vec4 outColor;",
    "void main() {",
    "  vec3 n = normalize(vNormal);",
    "  vec3 v = normalize(uEye - vWorld);",
    "  if (dot(n, v) < 0.0) n = -n;",
    "  vec3 l = normalize(uLight);",
    "  float diffuse = max(dot(n, l), 0.0);",
    "  float sky = 0.5 + 0.5 * n.y;",
    "  vec3 h = normalize(l + v);",
    "  float specular = uSpecular * 0.3 * pow(max(dot(n, h), 0.0), 40.0);",
    "  vec3 rgb = uColor.rgb * (0.22 + 0.63 * diffuse + 0.2 * sky) + vec3(specular);",
    "  outColor = vec4(min(rgb, vec3(1.0)), uColor.a);",
    "}"
  ].join("\n");

  var LINE_VS = [
    "#version 300 es",
    "layout(location = 0) in vec3 aPosition;",
    "uniform mat4 uViewProjection;",
    "void main() { gl_Position = uViewProjection * vec4(aPosition, 1.0); }"
  ].join("\n");

  var LINE_FS = [
    "#version 300 es",
    "precision mediump float;",
    "uniform vec4 uColor;",
    "out vec4 outColor;",
    "void main() { outColor = uColor; }"
  ].join("\n");

  function compile(type, source) {
    var shader = gl.createShader(type);
    gl.shaderSource(shader, source);
    gl.compileShader(shader);
    if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS)) {
      throw new Error("shader: " + gl.getShaderInfoLog(shader));
    }
    return shader;
  }
  function program(vs, fs, uniforms) {
    var p = gl.createProgram();
    gl.attachShader(p, compile(gl.VERTEX_SHADER, vs));
    gl.attachShader(p, compile(gl.FRAGMENT_SHADER, fs));
    gl.linkProgram(p);
    if (!gl.getProgramParameter(p, gl.LINK_STATUS)) throw new Error("program: " + gl.getProgramInfoLog(p));
    var u = { program: p };
    uniforms.forEach(function (name) { u[name] = gl.getUniformLocation(p, name); });
    return u;
  }

  function makeMesh(positions, normals, indices) {
    var vao = gl.createVertexArray();
    gl.bindVertexArray(vao);
    var pb = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, pb);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(positions), gl.STATIC_DRAW);
    gl.enableVertexAttribArray(0);
    gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 0, 0);
    var nb = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, nb);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(normals), gl.STATIC_DRAW);
    gl.enableVertexAttribArray(1);
    gl.vertexAttribPointer(1, 3, gl.FLOAT, false, 0, 0);
    var ib = gl.createBuffer();
    gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, ib);
    var wide = positions.length / 3 > 65535;
    gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, wide ? new Uint32Array(indices) : new Uint16Array(indices), gl.STATIC_DRAW);
    gl.bindVertexArray(null);
    return { vao: vao, count: indices.length, type: wide ? gl.UNSIGNED_INT : gl.UNSIGNED_SHORT, buffers: [pb, nb, ib] };
  }

  // Unit meshes. Sphere: diameter 1 about the origin. Cylinder, cone and
  // box: from x = 0 to x = 1, 1 wide in y and z (the cone's tip at x = 1).
  function sphereMesh(lat, lon) {
    var p = [], n = [], idx = [];
    for (var i = 0; i <= lat; i++) {
      var th = Math.PI * i / lat;
      for (var j = 0; j <= lon; j++) {
        var ph = 2 * Math.PI * j / lon;
        var v = [Math.sin(th) * Math.cos(ph), Math.cos(th), Math.sin(th) * Math.sin(ph)];
        n.push(v[0], v[1], v[2]);
        p.push(v[0] / 2, v[1] / 2, v[2] / 2);
      }
    }
    for (i = 0; i < lat; i++) {
      for (j = 0; j < lon; j++) {
        var a = i * (lon + 1) + j, b = a + lon + 1;
        idx.push(a, b, a + 1, a + 1, b, b + 1);
      }
    }
    return makeMesh(p, n, idx);
  }
  function cap(p, n, idx, x, nx, seg) {
    var center = p.length / 3;
    p.push(x, 0, 0); n.push(nx, 0, 0);
    for (var j = 0; j <= seg; j++) {
      var a = 2 * Math.PI * j / seg;
      p.push(x, Math.cos(a) / 2, Math.sin(a) / 2); n.push(nx, 0, 0);
      if (j > 0) idx.push(center, center + j, center + j + 1);
    }
  }
  function cylinderMesh(seg) {
    var p = [], n = [], idx = [];
    for (var j = 0; j <= seg; j++) {
      var a = 2 * Math.PI * j / seg, c = Math.cos(a), s = Math.sin(a);
      p.push(0, c / 2, s / 2, 1, c / 2, s / 2);
      n.push(0, c, s, 0, c, s);
      if (j < seg) idx.push(2 * j, 2 * j + 2, 2 * j + 1, 2 * j + 1, 2 * j + 2, 2 * j + 3);
    }
    cap(p, n, idx, 0, -1, seg);
    cap(p, n, idx, 1, 1, seg);
    return makeMesh(p, n, idx);
  }
  function coneMesh(seg) {
    var p = [], n = [], idx = [];
    for (var j = 0; j < seg; j++) {
      var a0 = 2 * Math.PI * j / seg, a1 = 2 * Math.PI * (j + 1) / seg, am = (a0 + a1) / 2;
      var base = p.length / 3;
      [a0, a1].forEach(function (a) {
        var nn = unit([0.5, Math.cos(a), Math.sin(a)]);
        p.push(0, Math.cos(a) / 2, Math.sin(a) / 2); n.push(nn[0], nn[1], nn[2]);
      });
      var nt = unit([0.5, Math.cos(am), Math.sin(am)]);
      p.push(1, 0, 0); n.push(nt[0], nt[1], nt[2]);
      idx.push(base, base + 2, base + 1);
    }
    cap(p, n, idx, 0, -1, seg);
    return makeMesh(p, n, idx);
  }
  function boxMesh() {
    var p = [], n = [], idx = [];
    var faces = [
      [[1, 0, 0], [[1, -1, -1], [1, 1, -1], [1, 1, 1], [1, -1, 1]]],
      [[-1, 0, 0], [[0, -1, -1], [0, -1, 1], [0, 1, 1], [0, 1, -1]]],
      [[0, 1, 0], [[0, 1, -1], [0, 1, 1], [1, 1, 1], [1, 1, -1]]],
      [[0, -1, 0], [[0, -1, -1], [1, -1, -1], [1, -1, 1], [0, -1, 1]]],
      [[0, 0, 1], [[0, -1, 1], [1, -1, 1], [1, 1, 1], [0, 1, 1]]],
      [[0, 0, -1], [[0, -1, -1], [0, 1, -1], [1, 1, -1], [1, -1, -1]]]
    ];
    faces.forEach(function (f) {
      var base = p.length / 3;
      f[1].forEach(function (c) { p.push(c[0], c[1] / 2, c[2] / 2); n.push(f[0][0], f[0][1], f[0][2]); });
      idx.push(base, base + 1, base + 2, base, base + 2, base + 3);
    });
    return makeMesh(p, n, idx);
  }
  // A helix's parameter grid: x = fraction along the coil, y = angle
  // around the wire; the vertex shader bends it into the coil.
  var helixMeshes = {};
  function helixMesh(windings) {
    var useg = Math.min(4000, Math.max(48, Math.ceil(windings * 32)));
    if (helixMeshes[useg]) return helixMeshes[useg];
    var vseg = 10, p = [], n = [], idx = [];
    for (var i = 0; i <= useg; i++) {
      for (var j = 0; j <= vseg; j++) {
        p.push(i / useg, 2 * Math.PI * j / vseg, 0);
        n.push(0, 0, 0);
      }
    }
    for (i = 0; i < useg; i++) {
      for (j = 0; j < vseg; j++) {
        var a = i * (vseg + 1) + j, b = a + vseg + 1;
        idx.push(a, b, a + 1, a + 1, b, b + 1);
      }
    }
    helixMeshes[useg] = makeMesh(p, n, idx);
    return helixMeshes[useg];
  }

  // The meshes of mesh files, each once (scene.meshes), for the "mesh" shapes.
  var fileMeshes = [];
  function loadFileMeshes() {
    fileMeshes.forEach(function (m) { gl.deleteVertexArray(m.vao); m.buffers.forEach(function (b) { gl.deleteBuffer(b); }); });
    fileMeshes = (scene.meshes || []).map(function (m) {
      var mesh = makeMesh(floats(m.positions), floats(m.normals), uints(m.indices));
      mesh.path = m.path;
      return mesh;
    });
  }

  var meshProgram = null, lineProgram = null, grid = null;
  if (gl) {
    meshProgram = program(MESH_VS, MESH_FS,
      ["uViewProjection", "uModel", "uNormalMatrix", "uHelix", "uColor", "uSpecular", "uEye", "uLight"]);
    lineProgram = program(LINE_VS, LINE_FS, ["uViewProjection", "uColor"]);
    // Coarser meshes for big scenes keep software renderers (no GPU) fluent.
    var coarse = shapes.length > 150;
    meshes = {
      sphere: coarse ? sphereMesh(10, 16) : sphereMesh(16, 28),
      cylinder: cylinderMesh(coarse ? 14 : 28),
      cone: coneMesh(coarse ? 14 : 28),
      box: boxMesh()
    };
    shapes.forEach(function (s) { if (s.kind === "helix") s.mesh = helixMesh(s.windings); });
    loadFileMeshes();
    canvas.addEventListener("webglcontextlost", function (e) {
      e.preventDefault();
      report("the WebGL context was lost: reload the page");
    });
  }

  // ------------------------------------------------------------ bounds, grid, camera
  // The world is drawn turned so that its up (against gravity, `scene.up`;
  // z for a robot from URDF) is the screen's up: `display` (rows) takes
  // world coordinates to those of the camera, grid and bounds, which keep y
  // up; `toDisplay` is it as a 4x4 for the view matrices.
  var display, toDisplay;
  function readUp() {
    var a = unit(scene.up || [0, 1, 0]), c = a[1];
    var v = [-a[2], 0, a[0]]; // a x y
    if (c < -1 + 1e-12) {
      display = [[1, 0, 0], [0, -1, 0], [0, 0, -1]];
    } else {
      // Rodrigues: c I + [v]x + v v' / (1 + c), the turn taking a to y.
      var k = 1 / (1 + c);
      display = [[c + v[0] * v[0] * k, -v[2] + v[0] * v[1] * k, v[1] + v[0] * v[2] * k],
                 [v[2] + v[1] * v[0] * k, c + v[1] * v[1] * k, -v[0] + v[1] * v[2] * k],
                 [-v[1] + v[2] * v[0] * k, v[0] + v[2] * v[1] * k, c + v[2] * v[2] * k]];
    }
    toDisplay = new Float32Array(16);
    for (var r = 0; r < 3; r++) for (var col = 0; col < 3; col++) toDisplay[col * 4 + r] = display[r][col];
    toDisplay[15] = 1;
  }
  // Display coordinates back to the world's (for the shader's eye and light).
  function toWorld(p) {
    return [display[0][0] * p[0] + display[1][0] * p[1] + display[2][0] * p[2],
            display[0][1] * p[0] + display[1][1] * p[1] + display[2][1] * p[2],
            display[0][2] * p[0] + display[1][2] * p[1] + display[2][2] * p[2]];
  }
  var bmin, bmax, center, radius;
  function readBounds() {
    readUp();
    bmin = [Infinity, Infinity, Infinity];
    bmax = [-Infinity, -Infinity, -Infinity];
    var lo = scene.bbox.min, hi = scene.bbox.max;
    for (var corner = 0; corner < 8; corner++) {
      var p = [corner & 1 ? hi[0] : lo[0], corner & 2 ? hi[1] : lo[1], corner & 4 ? hi[2] : lo[2]];
      for (var i = 0; i < 3; i++) {
        var x = display[i][0] * p[0] + display[i][1] * p[1] + display[i][2] * p[2];
        bmin[i] = Math.min(bmin[i], x);
        bmax[i] = Math.max(bmax[i], x);
      }
    }
    center = [(bmin[0] + bmax[0]) / 2, (bmin[1] + bmax[1]) / 2, (bmin[2] + bmax[2]) / 2];
    radius = Math.max(norm(sub(bmax, bmin)) / 2, 1e-3);
  }
  readBounds();

  function niceStep(x) {
    var e = Math.pow(10, Math.floor(Math.log10(x)));
    var f = x / e;
    return (f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10) * e;
  }
  function makeGrid() {
    var size = Math.max(bmax[0] - bmin[0], bmax[2] - bmin[2], radius) * 1.3;
    var step = niceStep(size / 10);
    var half = Math.ceil(size / 2 / step) * step;
    var cx = Math.round(center[0] / step) * step, cz = Math.round(center[2] / step) * step;
    var y = bmin[1] - 0.02 * radius;
    var p = [];
    for (var s = -half; s <= half + step / 2; s += step) {
      p.push(cx + s, y, cz - half, cx + s, y, cz + half);
      p.push(cx - half, y, cz + s, cx + half, y, cz + s);
    }
    var vao = gl.createVertexArray();
    gl.bindVertexArray(vao);
    var b = gl.createBuffer();
    gl.bindBuffer(gl.ARRAY_BUFFER, b);
    gl.bufferData(gl.ARRAY_BUFFER, new Float32Array(p), gl.STATIC_DRAW);
    gl.enableVertexAttribArray(0);
    gl.vertexAttribPointer(0, 3, gl.FLOAT, false, 0, 0);
    gl.bindVertexArray(null);
    return { vao: vao, buffer: b, count: p.length / 3 };
  }
  if (gl) grid = makeGrid();

  var FOVY = 40 * Math.PI / 180;
  var camera = { target: center.slice(), distance: 1, yaw: 0.5, pitch: 0.35 };
  // Whether the user moved the camera since it was last framed: a new
  // motion (setScene) is framed again only if not.
  var cameraMoved = false;
  function resetView() {
    cameraMoved = false;
    camera.target = center.slice();
    camera.yaw = 0.5;
    camera.pitch = 0.35;
    // The nearest distance at which all eight corners of the motion's
    // bounding box are in view, with a small margin.
    var aspect = Math.max(canvas.clientWidth, 1) / Math.max(canvas.clientHeight, 1);
    var tanY = Math.tan(FOVY / 2), tanX = tanY * aspect;
    var dir = eyeDirection();
    var axes = cameraAxes(addScaled(center, dir, 1), center);
    var distance = 1e-3;
    for (var c = 0; c < 8; c++) {
      var corner = [c & 1 ? bmax[0] : bmin[0], c & 2 ? bmax[1] : bmin[1], c & 4 ? bmax[2] : bmin[2]];
      var d = sub(corner, center);
      var x = dot(d, axes.x), y = dot(d, axes.y), z = dot(d, axes.z);
      distance = Math.max(distance, z + Math.abs(x) / tanX, z + Math.abs(y) / tanY);
    }
    camera.distance = distance * 1.08;
    state.dirty = true;
  }
  function eyeDirection() {
    var cp = Math.cos(camera.pitch);
    return [cp * Math.sin(camera.yaw), Math.sin(camera.pitch), cp * Math.cos(camera.yaw)];
  }

  // ------------------------------------------------------------ drawing
  var model = new Float32Array(16), normalMatrix = new Float32Array(9);
  var draws = 0;
  function drawMesh(mesh, origin, e1, e2, e3, sx, sy, sz, color, specular, helix) {
    if (!(sx > 0 && sy > 0 && sz > 0)) return;
    model[0] = e1[0] * sx; model[1] = e1[1] * sx; model[2] = e1[2] * sx; model[3] = 0;
    model[4] = e2[0] * sy; model[5] = e2[1] * sy; model[6] = e2[2] * sy; model[7] = 0;
    model[8] = e3[0] * sz; model[9] = e3[1] * sz; model[10] = e3[2] * sz; model[11] = 0;
    model[12] = origin[0]; model[13] = origin[1]; model[14] = origin[2]; model[15] = 1;
    normalMatrix[0] = e1[0] / sx; normalMatrix[1] = e1[1] / sx; normalMatrix[2] = e1[2] / sx;
    normalMatrix[3] = e2[0] / sy; normalMatrix[4] = e2[1] / sy; normalMatrix[5] = e2[2] / sy;
    normalMatrix[6] = e3[0] / sz; normalMatrix[7] = e3[1] / sz; normalMatrix[8] = e3[2] / sz;
    gl.uniformMatrix4fv(meshProgram.uModel, false, model);
    gl.uniformMatrix3fv(meshProgram.uNormalMatrix, false, normalMatrix);
    gl.uniform4f(meshProgram.uColor, color[0], color[1], color[2], color[3]);
    gl.uniform1f(meshProgram.uSpecular, specular);
    if (helix) gl.uniform4f(meshProgram.uHelix, helix[0], helix[1], helix[2], helix[3]);
    else gl.uniform4f(meshProgram.uHelix, 0, 0, 0, 0);
    gl.bindVertexArray(mesh.vao);
    gl.drawElements(gl.TRIANGLES, mesh.count, mesh.type, 0);
    draws++;
  }

  // A mesh placed by a general affine map: `m` the 3x3 part (row-major),
  // `n` its normal matrix (row-major), `o` the origin, all in the world.
  function drawAffine(mesh, m, n, o, color, specular) {
    model[0] = m[0]; model[1] = m[3]; model[2] = m[6]; model[3] = 0;
    model[4] = m[1]; model[5] = m[4]; model[6] = m[7]; model[7] = 0;
    model[8] = m[2]; model[9] = m[5]; model[10] = m[8]; model[11] = 0;
    model[12] = o[0]; model[13] = o[1]; model[14] = o[2]; model[15] = 1;
    normalMatrix[0] = n[0]; normalMatrix[1] = n[3]; normalMatrix[2] = n[6];
    normalMatrix[3] = n[1]; normalMatrix[4] = n[4]; normalMatrix[5] = n[7];
    normalMatrix[6] = n[2]; normalMatrix[7] = n[5]; normalMatrix[8] = n[8];
    gl.uniformMatrix4fv(meshProgram.uModel, false, model);
    gl.uniformMatrix3fv(meshProgram.uNormalMatrix, false, normalMatrix);
    gl.uniform4f(meshProgram.uColor, color[0], color[1], color[2], color[3]);
    gl.uniform1f(meshProgram.uSpecular, specular);
    gl.uniform4f(meshProgram.uHelix, 0, 0, 0, 0);
    gl.bindVertexArray(mesh.vao);
    gl.drawElements(gl.TRIANGLES, mesh.count, mesh.type, 0);
    draws++;
  }
  // Row-major 3x3 products: the frame's rotation (at `o` in poseRotation) times `a`.
  var worldLinear = new Float64Array(9), worldNormal = new Float64Array(9);
  function rotateInto(out, r, o, a) {
    for (var i = 0; i < 3; i++) {
      for (var j = 0; j < 3; j++) {
        out[3 * i + j] = r[o + 3 * i] * a[j] + r[o + 3 * i + 1] * a[3 + j] + r[o + 3 * i + 2] * a[6 + j];
      }
    }
    return out;
  }
  function drawFileMesh(s) {
    var mesh = fileMeshes[s.meshIndex];
    if (!mesh) return;
    var o = s.pose * 9;
    var origin = addScaled(positionOf(s.pose), apply3(poseRotation, o, s.offset), 1);
    drawAffine(mesh, rotateInto(worldLinear, poseRotation, o, s.linear),
      rotateInto(worldNormal, poseRotation, o, s.cofactor), origin, s.color, s.specular);
  }

  function drawArrow(origin, e1, e2, e3, length, width, color, specular) {
    if (!(length > 0)) return;
    var head = Math.min(0.4 * length, 4 * width);
    var headWidth = 2.5 * width;
    var shaft = length - head;
    if (shaft > 0) drawMesh(meshes.cylinder, origin, e1, e2, e3, shaft, width, width, color, specular);
    drawMesh(meshes.cone, addScaled(origin, e1, shaft), e1, e2, e3, head, headWidth, headWidth, color, specular);
  }

  function drawShape(s) {
    if (s.kind === "mesh") { drawFileMesh(s); return; }
    var at = placeShape(s);
    var o = at.origin, e1 = at.e1, e2 = at.e2, e3 = at.e3, length = at.length;
    switch (s.kind) {
      case "sphere":
        drawMesh(meshes.sphere, o, e1, e2, e3, s.width, s.width, s.width, s.color, s.specular);
        break;
      case "cylinder":
        drawMesh(meshes.cylinder, o, e1, e2, e3, length, s.width, s.height, s.color, s.specular);
        break;
      case "line":
        drawMesh(meshes.cylinder, o, e1, e2, e3, length, s.width, s.width, s.color, s.specular);
        break;
      case "box":
        drawMesh(meshes.box, o, e1, e2, e3, length, s.width, s.height, s.color, s.specular);
        break;
      case "cone":
        drawMesh(meshes.cone, o, e1, e2, e3, length, s.width, s.height, s.color, s.specular);
        break;
      case "arrow":
        drawArrow(o, e1, e2, e3, length, s.width, s.color, s.specular);
        break;
      case "helix":
        var wire = s.height < s.width ? s.height : s.width / 10;
        if (length > 0) {
          drawMesh(s.mesh, o, e1, e2, e3, 1, 1, 1, s.color, s.specular,
            [length, s.width / 2, wire / 2, Math.max(s.windings, 0.5)]);
        }
        break;
      default:
        break;
    }
  }

  var TRIAD_COLORS = [[0.85, 0.1, 0.1, 1], [0.1, 0.6, 0.1, 1], [0.1, 0.25, 0.9, 1]];
  var TRIAD_CSS = ["#c41a1a", "#198a19", "#1a40e0"];
  var axisLabels = document.querySelectorAll("#mb-axis-labels span");

  function resizeCanvas() {
    var dpr = window.devicePixelRatio || 1;
    var w = Math.max(1, Math.round(canvas.clientWidth * dpr));
    var h = Math.max(1, Math.round(canvas.clientHeight * dpr));
    if (canvas.width !== w || canvas.height !== h) {
      canvas.width = w;
      canvas.height = h;
    }
    return dpr;
  }

  function render3d() {
    if (!gl) return;
    var dpr = resizeCanvas();
    var w = canvas.width, h = canvas.height;
    gl.viewport(0, 0, w, h);
    gl.clearColor(0.93, 0.94, 0.96, 1);
    gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
    gl.enable(gl.DEPTH_TEST);
    gl.disable(gl.CULL_FACE);
    updatePoses(state.t);

    var dir = eyeDirection();
    var eye = addScaled(camera.target, dir, camera.distance);
    var axes = cameraAxes(eye, camera.target);
    var near = camera.distance / 200, far = camera.distance * 20 + radius * 4;
    var viewProjection = multiply(perspective(FOVY, w / h, near, far), lookAt(eye, axes));

    // The grid lies in display coordinates; everything else is the world's.
    gl.useProgram(lineProgram.program);
    gl.uniformMatrix4fv(lineProgram.uViewProjection, false, viewProjection);
    gl.uniform4f(lineProgram.uColor, 0.72, 0.74, 0.78, 1);
    gl.bindVertexArray(grid.vao);
    gl.drawArrays(gl.LINES, 0, grid.count);

    gl.useProgram(meshProgram.program);
    gl.uniformMatrix4fv(meshProgram.uViewProjection, false, multiply(viewProjection, toDisplay));
    var worldEye = toWorld(eye);
    gl.uniform3f(meshProgram.uEye, worldEye[0], worldEye[1], worldEye[2]);
    // A light above and to the left of the camera, turning with it.
    var light = toWorld(addScaled(addScaled(axes.z, axes.y, 0.8), axes.x, -0.45));
    gl.uniform3f(meshProgram.uLight, light[0], light[1], light[2]);
    draws = 0;
    var i;
    for (i = 0; i < shapes.length; i++) if (!shapes[i].transparent) drawShape(shapes[i]);
    gl.enable(gl.BLEND);
    gl.blendFunc(gl.SRC_ALPHA, gl.ONE_MINUS_SRC_ALPHA);
    gl.depthMask(false);
    for (i = 0; i < shapes.length; i++) if (shapes[i].transparent) drawShape(shapes[i]);
    gl.depthMask(true);
    gl.disable(gl.BLEND);

    // The axis triad in the lower left corner, turning with the camera.
    var size = Math.round(78 * dpr);
    gl.enable(gl.SCISSOR_TEST);
    gl.scissor(0, 0, size, size);
    gl.clear(gl.DEPTH_BUFFER_BIT);
    gl.disable(gl.SCISSOR_TEST);
    gl.viewport(0, 0, size, size);
    var triadEye = scale(dir, 4);
    var triadViewProjection = multiply(
      multiply(orthographic(1.45, 0.1, 10), lookAt(triadEye, cameraAxes(triadEye, [0, 0, 0]))), toDisplay);
    gl.uniformMatrix4fv(meshProgram.uViewProjection, false, triadViewProjection);
    var triadWorldEye = toWorld(triadEye);
    gl.uniform3f(meshProgram.uEye, triadWorldEye[0], triadWorldEye[1], triadWorldEye[2]);
    var basis = [[1, 0, 0], [0, 1, 0], [0, 0, 1]];
    for (i = 0; i < 3; i++) {
      var e1 = basis[i], e2 = basis[(i + 1) % 3], e3 = basis[(i + 2) % 3];
      drawArrow([0, 0, 0], e1, e2, e3, 1, 0.09, TRIAD_COLORS[i], 0.5);
      var tip = transformPoint(triadViewProjection, scale(e1, 1.28));
      var label = axisLabels[i];
      if (label) {
        label.style.color = TRIAD_CSS[i];
        label.style.left = ((tip[0] * 0.5 + 0.5) * size / dpr) + "px";
        label.style.top = (canvas.clientHeight - (tip[1] * 0.5 + 0.5) * size / dpr) + "px";
      }
    }
    gl.viewport(0, 0, w, h);
    gl.bindVertexArray(null);
  }

  // ------------------------------------------------------------ plots
  var plotsBox = document.getElementById("mb-plots");
  var PLOT_COLOR = "#1f5fbf";
  var MARGIN = { left: 58, right: 12, top: 20, bottom: 22 };
  var plotTimes, plots, pt0, pt1;
  // A plot of the signal `s`, drawn on `canvas` (a new one when not given).
  function makePlot(s, canvas) {
    var c = canvas || document.createElement("canvas");
    c.title = s.name + (s.unit ? " [" + s.unit + "]" : "") + ": click or drag to seek";
    if (!canvas) plotsBox.appendChild(c);
    var data = floats(s.data);
    var lo = Infinity, hi = -Infinity;
    for (var i = 0; i < data.length; i++) {
      if (isFinite(data[i])) { lo = Math.min(lo, data[i]); hi = Math.max(hi, data[i]); }
    }
    if (!isFinite(lo)) { lo = -1; hi = 1; }
    if (hi - lo < 1e-12 * Math.max(1, Math.abs(hi))) { lo -= 0.5 * Math.max(1e-6, Math.abs(lo)); hi += 0.5 * Math.max(1e-6, Math.abs(hi)); }
    var pad = 0.06 * (hi - lo);
    var plot = { name: s.name, unit: s.unit, data: data, canvas: c, lo: lo - pad, hi: hi + pad, back: null, width: 0, height: 0 };
    if (!canvas) attachSeek(plot);
    return plot;
  }
  function makePlots() {
    plotTimes = floats(scene.signalTimes);
    // The same signals again (a live page's next run): their canvases stay.
    var old = plots || [];
    var same = old.length > 0 && old.length === scene.signals.length &&
      old.every(function (p, i) { return p.name === scene.signals[i].name; });
    if (same) {
      plots = scene.signals.map(function (s, i) { return makePlot(s, old[i].canvas); });
    } else {
      plotsBox.textContent = "";
      plots = scene.signals.map(function (s) { return makePlot(s); });
    }
    if (!plots.length) {
      var empty = document.createElement("div");
      empty.className = "mb-empty";
      empty.textContent = "No signals chosen to plot.";
      plotsBox.appendChild(empty);
    }
    pt0 = plotTimes.length ? plotTimes[0] : tStart;
    pt1 = plotTimes.length ? plotTimes[plotTimes.length - 1] : tEnd;
    if (!(pt1 > pt0)) pt1 = pt0 + 1;
  }
  makePlots();

  function ticks(lo, hi, count) {
    var step = niceStep((hi - lo) / count);
    var out = [];
    for (var v = Math.ceil(lo / step) * step; v <= hi + step * 1e-9; v += step) out.push(Math.abs(v) < step * 1e-9 ? 0 : v);
    return out;
  }
  function format(x) {
    if (x === 0) return "0";
    var a = Math.abs(x);
    if (a >= 1e5 || a < 1e-3) return x.toExponential(2);
    return String(parseFloat(x.toPrecision(4)));
  }
  function plotX(p, t) { return MARGIN.left + (t - pt0) / (pt1 - pt0) * (p.width - MARGIN.left - MARGIN.right); }
  function plotY(p, v) { return MARGIN.top + (p.hi - v) / (p.hi - p.lo) * (p.height - MARGIN.top - MARGIN.bottom); }

  function drawPlotBack(p, dpr) {
    var back = p.back || document.createElement("canvas");
    back.width = p.canvas.width;
    back.height = p.canvas.height;
    var ctx = back.getContext("2d");
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.fillStyle = "#fff";
    ctx.fillRect(0, 0, p.width, p.height);
    var x0 = MARGIN.left, x1 = p.width - MARGIN.right, y0 = MARGIN.top, y1 = p.height - MARGIN.bottom;
    ctx.font = "10px sans-serif";
    ctx.lineWidth = 1;
    ctx.strokeStyle = "#e3e6ea";
    ctx.fillStyle = "#555";
    ctx.textAlign = "right";
    ctx.textBaseline = "middle";
    ticks(p.lo, p.hi, 4).forEach(function (v) {
      var y = Math.round(plotY(p, v)) + 0.5;
      ctx.beginPath(); ctx.moveTo(x0, y); ctx.lineTo(x1, y); ctx.stroke();
      ctx.fillText(format(v), x0 - 4, y);
    });
    ctx.textAlign = "center";
    ctx.textBaseline = "top";
    ticks(pt0, pt1, Math.max(2, Math.floor((x1 - x0) / 70))).forEach(function (t) {
      var x = Math.round(plotX(p, t)) + 0.5;
      ctx.beginPath(); ctx.moveTo(x, y0); ctx.lineTo(x, y1); ctx.stroke();
      ctx.fillText(format(t), x, y1 + 3);
    });
    ctx.textAlign = "left";
    ctx.fillText("t [s]", 4, y1 + 3);
    ctx.strokeStyle = "#99a";
    ctx.strokeRect(x0 + 0.5, y0 + 0.5, x1 - x0 - 1, y1 - y0 - 1);
    ctx.save();
    ctx.beginPath();
    ctx.rect(x0, y0, x1 - x0, y1 - y0);
    ctx.clip();
    ctx.strokeStyle = PLOT_COLOR;
    ctx.lineWidth = 1.5;
    ctx.beginPath();
    var pen = false;
    for (var i = 0; i < p.data.length; i++) {
      var v = p.data[i];
      if (!isFinite(v)) { pen = false; continue; }
      var x = plotX(p, plotTimes[i]), y = plotY(p, v);
      if (pen) ctx.lineTo(x, y); else ctx.moveTo(x, y);
      pen = true;
    }
    ctx.stroke();
    ctx.restore();
    ctx.fillStyle = "#222";
    ctx.font = "bold 11px sans-serif";
    ctx.textAlign = "left";
    ctx.textBaseline = "alphabetic";
    ctx.fillText(p.name + (p.unit ? " [" + p.unit + "]" : ""), x0, 14);
    p.back = back;
  }

  function valueAt(p, t) {
    var n = plotTimes.length;
    if (!n) return NaN;
    if (t <= plotTimes[0]) return p.data[0];
    if (t >= plotTimes[n - 1]) return p.data[n - 1];
    var lo = 0, hi = n - 1;
    while (hi - lo > 1) { var mid = (lo + hi) >> 1; if (plotTimes[mid] <= t) lo = mid; else hi = mid; }
    var w = (t - plotTimes[lo]) / ((plotTimes[hi] - plotTimes[lo]) || 1);
    return p.data[lo] * (1 - w) + p.data[hi] * w;
  }

  function renderPlots() {
    var dpr = window.devicePixelRatio || 1;
    for (var i = 0; i < plots.length; i++) {
      var p = plots[i];
      var cw = p.canvas.clientWidth, ch = p.canvas.clientHeight;
      if (!cw || !ch) continue;
      if (cw !== p.width || ch !== p.height || !p.back || p.canvas.width !== Math.round(cw * dpr)) {
        p.width = cw; p.height = ch;
        p.canvas.width = Math.round(cw * dpr);
        p.canvas.height = Math.round(ch * dpr);
        drawPlotBack(p, dpr);
      }
      var ctx = p.canvas.getContext("2d");
      ctx.setTransform(1, 0, 0, 1, 0, 0);
      ctx.drawImage(p.back, 0, 0);
      ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
      var x = plotX(p, state.t);
      ctx.strokeStyle = "#d23";
      ctx.lineWidth = 1;
      ctx.beginPath();
      ctx.moveTo(x, MARGIN.top);
      ctx.lineTo(x, p.height - MARGIN.bottom);
      ctx.stroke();
      var v = valueAt(p, state.t);
      ctx.fillStyle = "#d23";
      ctx.font = "11px sans-serif";
      ctx.textAlign = "right";
      ctx.textBaseline = "alphabetic";
      ctx.fillText(format(v), p.width - MARGIN.right, 14);
    }
  }

  // Keeps a drag going outside the element (not possible for every pointer).
  function capture(element, e) {
    try { element.setPointerCapture(e.pointerId); } catch (err) { /* a synthetic or finished pointer */ }
  }

  function attachSeek(p) {
    var seeking = false;
    function seek(e) {
      var r = p.canvas.getBoundingClientRect();
      var f = (e.clientX - r.left - MARGIN.left) / Math.max(1, r.width - MARGIN.left - MARGIN.right);
      setTime(pt0 + Math.min(1, Math.max(0, f)) * (pt1 - pt0));
    }
    p.canvas.addEventListener("pointerdown", function (e) { seeking = true; capture(p.canvas, e); seek(e); });
    p.canvas.addEventListener("pointermove", function (e) { if (seeking) seek(e); });
    p.canvas.addEventListener("pointerup", function () { seeking = false; });
    p.canvas.addEventListener("pointercancel", function () { seeking = false; });
  }

  // ------------------------------------------------------------ playback and controls
  var state = {
    t: tStart,
    playing: !!scene.autoplay && tEnd > tStart,
    speed: scene.speed > 0 ? scene.speed : 1,
    loop: !!scene.loop,
    dirty: true
  };
  var playButton = document.getElementById("mb-play");
  var slider = document.getElementById("mb-slider");
  var timeLabel = document.getElementById("mb-time");
  var speedSelect = document.getElementById("mb-speed");
  var loopBox = document.getElementById("mb-loop");

  function setSliderRange() {
    slider.min = String(tStart);
    slider.max = String(tEnd > tStart ? tEnd : tStart + 1);
  }
  setSliderRange();
  var speeds = [0.05, 0.1, 0.25, 0.5, 1, 2, 5, 10];
  if (speeds.indexOf(state.speed) < 0) { speeds.push(state.speed); speeds.sort(function (a, b) { return a - b; }); }
  speeds.forEach(function (s) {
    var o = document.createElement("option");
    o.value = String(s);
    o.textContent = s + "\u00d7";
    if (s === state.speed) o.selected = true;
    speedSelect.appendChild(o);
  });
  loopBox.checked = state.loop;

  function setTime(t) {
    if (!isFinite(t)) return;
    state.t = Math.min(tEnd, Math.max(tStart, t));
    state.dirty = true;
  }
  function setPlaying(on) {
    state.playing = !!on && tEnd > tStart;
    if (state.playing && state.t >= tEnd) state.t = tStart;
    state.dirty = true;
  }
  function updateControls() {
    playButton.textContent = state.playing ? "Pause" : "Play";
    slider.value = String(state.t);
    var digits = tEnd - tStart >= 100 ? 1 : 3;
    timeLabel.textContent = "t = " + state.t.toFixed(digits) + " s / " + tEnd.toFixed(digits) + " s";
  }

  playButton.addEventListener("click", function () { setPlaying(!state.playing); });
  slider.addEventListener("input", function () { setTime(parseFloat(slider.value)); });
  speedSelect.addEventListener("change", function () { state.speed = parseFloat(speedSelect.value) || 1; });
  loopBox.addEventListener("change", function () { state.loop = loopBox.checked; });
  document.getElementById("mb-reset").addEventListener("click", resetView);
  document.addEventListener("keydown", function (e) {
    var tag = e.target && e.target.tagName;
    if (tag === "INPUT" || tag === "SELECT" || tag === "BUTTON" || tag === "TEXTAREA") return;
    var step = frameCount > 1 ? (tEnd - tStart) / (frameCount - 1) : 0;
    if (e.key === " ") { setPlaying(!state.playing); e.preventDefault(); }
    else if (e.key === "r" || e.key === "R") resetView();
    else if (e.key === "ArrowRight") { state.playing = false; setTime(state.t + step); }
    else if (e.key === "ArrowLeft") { state.playing = false; setTime(state.t - step); }
    else if (e.key === "Home") setTime(tStart);
    else if (e.key === "End") setTime(tEnd);
  });

  // Orbit camera: drag rotates, right or shift drag (or two fingers) pans,
  // the wheel zooms, a double click frames the motion.
  var drag = null;
  canvas.addEventListener("contextmenu", function (e) { e.preventDefault(); });
  canvas.addEventListener("pointerdown", function (e) {
    drag = { x: e.clientX, y: e.clientY, pan: e.button === 2 || e.button === 1 || e.shiftKey };
    capture(canvas, e);
    canvas.classList.add("mb-dragging");
  });
  canvas.addEventListener("pointermove", function (e) {
    if (!drag) return;
    var dx = e.clientX - drag.x, dy = e.clientY - drag.y;
    drag.x = e.clientX; drag.y = e.clientY;
    if (drag.pan) {
      var dir = eyeDirection();
      var axes = cameraAxes(addScaled(camera.target, dir, camera.distance), camera.target);
      var k = 2 * camera.distance * Math.tan(FOVY / 2) / Math.max(1, canvas.clientHeight);
      camera.target = addScaled(addScaled(camera.target, axes.x, -dx * k), axes.y, dy * k);
    } else {
      camera.yaw -= dx * 0.008;
      camera.pitch = Math.max(-1.55, Math.min(1.55, camera.pitch + dy * 0.008));
    }
    cameraMoved = true;
    state.dirty = true;
  });
  function endDrag() { drag = null; canvas.classList.remove("mb-dragging"); }
  canvas.addEventListener("pointerup", endDrag);
  canvas.addEventListener("pointercancel", endDrag);
  canvas.addEventListener("wheel", function (e) {
    e.preventDefault();
    var delta = e.deltaY * (e.deltaMode === 1 ? 40 : e.deltaMode === 2 ? 400 : 1);
    camera.distance = Math.min(radius * 1e3, Math.max(radius * 1e-3, camera.distance * Math.exp(delta * 0.0015)));
    cameraMoved = true;
    state.dirty = true;
  }, { passive: false });
  canvas.addEventListener("dblclick", resetView);
  window.addEventListener("resize", function () { state.dirty = true; });

  function render() {
    render3d();
    renderPlots();
    updateControls();
    state.dirty = false;
  }

  var last = null;
  function tick(now) {
    if (state.playing) {
      if (last !== null) {
        var t = state.t + Math.min(0.1, (now - last) / 1000) * state.speed;
        if (t >= tEnd) {
          if (state.loop) t = tStart + (t - tEnd) % Math.max(tEnd - tStart, 1e-9);
          else { t = tEnd; state.playing = false; }
        }
        state.t = t;
      }
      last = now;
      state.dirty = true;
    } else {
      last = null;
    }
    if (state.dirty) render();
    window.requestAnimationFrame(tick);
  }

  // A new motion of the same model (a live page's next run): the view,
  // the time and the playing state stay; the plots and bounds follow.
  function setScene(next, keepView) {
    scene = next;
    readMotion();
    shapes = scene.shapes.map(makeShape);
    readBounds();
    if (gl) {
      if (grid) { gl.deleteVertexArray(grid.vao); gl.deleteBuffer(grid.buffer); }
      grid = makeGrid();
      loadFileMeshes();
    }
    makePlots();
    setSliderRange();
    if (!cameraMoved && !keepView) resetView();
    state.t = Math.min(tEnd, Math.max(tStart, state.t));
    if (state.playing && !(tEnd > tStart)) state.playing = false;
    var info = window.__multibody.info;
    info.frames = frameCount; info.poses = poseCount; info.shapes = shapes.length;
    info.signals = plots.length; info.start = tStart; info.stop = tEnd;
    render();
  }

  window.__multibody = {
    setScene: setScene,
    setTime: function (t) { setTime(t); render(); },
    time: function () { return state.t; },
    play: function () { setPlaying(true); },
    pause: function () { setPlaying(false); },
    resetView: resetView,
    render: render,
    info: { frames: frameCount, poses: poseCount, shapes: shapes.length, signals: plots.length, start: tStart, stop: tEnd },
    draws: function () { return draws; },
    errors: window.__multibodyErrors
  };

  if (query.get("panel") === "0") document.body.classList.add("mb-bare");
  resetView();
  if (query.has("t")) {
    state.playing = false;
    setTime(parseFloat(query.get("t")));
    render();
    console.log("multibody-view: rendered t=" + state.t + " draws=" + draws);
  } else {
    render();
  }
  // Drives every control through DOM events, as a person would, and logs
  // what changed: the tests use it to check that the controls work.
  function exercise() {
    var r = canvas.getBoundingClientRect();
    var cx = r.left + r.width / 2, cy = r.top + r.height / 2;
    function pointer(target, type, x, y, extra) {
      var init = { clientX: x, clientY: y, pointerId: 7, button: 0, bubbles: true, cancelable: true };
      for (var k in extra || {}) init[k] = extra[k];
      target.dispatchEvent(new PointerEvent(type, init));
    }
    var before = { yaw: camera.yaw, pitch: camera.pitch, distance: camera.distance, target: camera.target.slice() };
    var checks = {};
    playButton.click();
    checks.play = state.playing === (tEnd > tStart);
    playButton.click();
    checks.pause = !state.playing;
    slider.value = String(tStart + 0.25 * (tEnd - tStart));
    slider.dispatchEvent(new Event("input", { bubbles: true }));
    checks.slider = Math.abs(state.t - (tStart + 0.25 * (tEnd - tStart))) < 1e-6 * Math.max(1, tEnd);
    speedSelect.value = speedSelect.options[speedSelect.options.length - 1].value;
    speedSelect.dispatchEvent(new Event("change", { bubbles: true }));
    checks.speed = state.speed === parseFloat(speedSelect.value);
    loopBox.click();
    checks.loop = state.loop === !scene.loop;
    loopBox.click();
    var t = state.t;
    document.body.dispatchEvent(new KeyboardEvent("keydown", { key: "ArrowRight", bubbles: true }));
    checks.key = frameCount < 2 || state.t > t;
    if (plots.length && plots[0].canvas.clientWidth) {
      var pr = plots[0].canvas.getBoundingClientRect();
      var px = pr.left + MARGIN.left + 0.75 * (pr.width - MARGIN.left - MARGIN.right);
      pointer(plots[0].canvas, "pointerdown", px, pr.top + 40);
      pointer(plots[0].canvas, "pointerup", px, pr.top + 40);
      checks.plotSeek = Math.abs(state.t - (pt0 + 0.75 * (pt1 - pt0))) < 0.02 * (pt1 - pt0);
    }
    pointer(canvas, "pointerdown", cx, cy, { shiftKey: true });
    pointer(canvas, "pointermove", cx + 40, cy + 15, { shiftKey: true });
    pointer(canvas, "pointerup", cx + 40, cy + 15, { shiftKey: true });
    checks.pan = norm(sub(camera.target, before.target)) > 0;
    pointer(canvas, "pointerdown", cx, cy);
    pointer(canvas, "pointermove", cx + 60, cy + 20);
    pointer(canvas, "pointerup", cx + 60, cy + 20);
    checks.rotate = camera.yaw < before.yaw && camera.pitch > before.pitch;
    canvas.dispatchEvent(new WheelEvent("wheel", { deltaY: -240, clientX: cx, clientY: cy, bubbles: true, cancelable: true }));
    checks.zoom = camera.distance < before.distance;
    document.getElementById("mb-reset").click();
    checks.reset = camera.yaw === before.yaw && Math.abs(camera.distance - before.distance) < 1e-9 * before.distance;
    pointer(canvas, "pointerdown", cx, cy);
    pointer(canvas, "pointermove", cx - 120, cy + 40);
    pointer(canvas, "pointerup", cx - 120, cy + 40);
    render();
    var failed = Object.keys(checks).filter(function (k) { return !checks[k]; });
    console.log("multibody-view: exercised " + Object.keys(checks).join(",") + (failed.length ? " FAILED " + failed.join(",") : " all ok"));
  }
  if (query.has("exercise")) exercise();

  if (query.has("bench")) {
    var n = Math.max(1, parseInt(query.get("bench"), 10) || 30);
    var started = performance.now();
    for (var b = 0; b < n; b++) {
      setTime(tStart + (tEnd - tStart) * b / n);
      render();
    }
    if (gl) gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, new Uint8Array(4));
    var ms = (performance.now() - started) / n;
    window.__multibody.benchMs = ms;
    console.log("multibody-view: bench frames=" + n + " ms_per_frame=" + ms.toFixed(2) + " draws=" + draws);
    setTime(query.has("t") ? parseFloat(query.get("t")) : tStart);
    render();
  }
  window.requestAnimationFrame(tick);
})();
