// The armanim viewer page: draws one run's frames with three.js (window.THREE).
// Every position comes from the data block, computed by armanim's forward kinematics in
// Python; this code only places solids where the data says. Text from the data is set
// with textContent, never as markup. Page API: window.armanim (docs/viewer.md).
"use strict";
(function () {
  const D = JSON.parse(document.getElementById("armanim-data").textContent);
  const F = D.frames, N = D.joints.length, P = N + 1, S = D.style;
  const $ = (id) => document.getElementById(id);
  const clamp = (v, lo, hi) => Math.max(lo, Math.min(hi, v));
  // A long run's page holds one frame in D.step (docs/viewer.md): the page's frame f is the run's frame runFrame(f).
  const STEP = D.step || 1, RUN_LAST = (D.run_frames || F) - 1;
  const runFrame = (f) => Math.min(f * STEP, RUN_LAST);
  const PLOT_COLORS = ["#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#17becf"];

  // ---- the state, and the page API -------------------------------------------------
  // Playing is a function of the clock: frame = f0 + floor(elapsed * fps * speed), so the
  // frame is right whenever it is read, however often the browser draws.
  const st = { frame: 0, playing: false, speed: 1, t0: 0, f0: 0, shown: -1, shownPlaying: null, dirty: true, drawn: 0 };
  function sync(now) {
    if (!st.playing) return;
    const f = st.f0 + Math.floor(((now === undefined ? performance.now() : now) - st.t0) / 1000 * D.fps / STEP * st.speed);
    if (f >= F - 1) { st.frame = F - 1; st.playing = false; } else st.frame = Math.max(f, 0);
  }
  function anchor() { st.t0 = performance.now(); st.f0 = st.frame; }
  function setFrame(k) {
    sync();
    k = Math.round(Number(k));
    st.frame = clamp(Number.isFinite(k) ? k : 0, 0, F - 1);
    if (st.playing) anchor();
    show();
  }
  function play() {
    sync();
    if (st.frame >= F - 1) st.frame = 0;
    st.playing = F > 1;
    anchor(); show();
  }
  function pause() { sync(); st.playing = false; show(); }
  function setSpeed(s) {
    sync(); st.speed = clamp(Number(s) || 1, 0.25, 4); anchor();
    const sel = $("speed"); if (Number(sel.value) !== st.speed) sel.value = String(st.speed);
  }
  const api = {
    get frame() { sync(); return st.frame; },
    frames: F,
    fps: D.fps,
    step: STEP,
    get playing() { sync(); return st.playing; },
    get speed() { return st.speed; },
    get drawn() { return st.drawn; },
    ready: false,
    webgl: false,
    data: D,
    setFrame, play, pause, setSpeed,
    setView: (name) => setView(name),
    goalStates: (k) => goalStates(k === undefined ? api.frame : k),
    nextDraw: () => new Promise((resolve) => { if (!renderer) resolve(0); else { waiters.push(resolve); st.dirty = true; } }),
  };
  const waiters = [];
  window.armanim = api;

  // ---- what a frame says ---------------------------------------------------------
  const passingCode = D.activities.indexOf("passing");  // a via goal passed within its radius without stopping
  function goalStates(f) {
    const k = D.goal[f];
    return D.goals.map((g, j) => {
      if (f === F - 1 || j < k || (g.last >= 0 && f >= g.last)) return g.reached ? "reached" : "missed";
      if (j === k) return D.reached[f] || D.activity[f] === passingCode ? "reached" : "current";
      return "pending";
    });
  }
  const fixed = (v, d) => (v === null || v === undefined ? "none" : v.toFixed(d));

  // ---- the page's fixed parts ------------------------------------------------------
  $("title").textContent = D.title;
  if (!D.obstacles.length && !D.boxes && !D.obstacle_capsules && !D.cylinders && D.clearance.every((v) => v === null)) $("clearance").parentElement.hidden = true;  // no obstacles (nor floor): no clearance to show
  document.title = D.title + " - armanim";
  const slider = $("slider");
  slider.max = String(F - 1);
  $("last").textContent = String(RUN_LAST) + (STEP > 1 ? ` (one frame in ${STEP} shown)` : "");
  const tbody = document.querySelector("#angles tbody"), angleCells = [];
  D.joints.forEach((name, j) => {
    const tr = document.createElement("tr"), th = document.createElement("td"), td = document.createElement("td");
    th.textContent = name; th.style.setProperty("--c", PLOT_COLORS[j % PLOT_COLORS.length]);
    td.className = "angle"; td.dataset.joint = String(j);
    tr.append(th, td); tbody.append(tr); angleCells.push(td);
  });
  const labels = D.goals.map((g, i) => {
    const el = document.createElement("div");
    const ring = document.createElement("span"), num = document.createElement("span");
    ring.className = "ring"; num.className = "num"; num.textContent = String(i);
    el.className = "goal-label"; el.dataset.goal = String(i); el.append(ring, num);
    $("labels").append(el); return el;
  });

  // ---- the 3-D scene (world z up, as in armanim) --------------------------------------
  const T = window.THREE, view = $("view");
  const box = D.view.box, lo = new T.Vector3(...box[0]), hi = new T.Vector3(...box[1]);
  const center = lo.clone().add(hi).multiplyScalar(0.5), size = Math.max(hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-9);
  const hw = D.arm.half_width;
  let renderer = null;
  try {
    renderer = new T.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
  } catch (e) {
    $("nogl").hidden = false;
    $("labels").hidden = true;  // nothing to label
  }
  const scene = new T.Scene();
  scene.background = new T.Color(S.background);
  const camera = new T.OrthographicCamera(-1, 1, 1, -1, size * 0.001, size * 100);
  camera.up.set(0, 0, 1);
  scene.add(camera);
  scene.add(new T.HemisphereLight(0xffffff, 0x8a8d96, 1.1));
  const key = new T.DirectionalLight(0xffffff, 1.9);  // the video's light: from the viewer's upper left
  key.position.set(-0.45, 0.6, 0.66); camera.add(key); camera.add(key.target);
  const sun = new T.DirectionalLight(0xffffff, 0.6);  // overhead, for the shadows on the floor (as in the video)
  const fl = D.view.floor;
  sun.position.set(center.x, center.y, hi.z + size); sun.target.position.set(center.x, center.y, fl.z);
  sun.castShadow = true;
  const half = size * 0.75;
  Object.assign(sun.shadow.camera, { left: -half, right: half, top: half, bottom: -half, near: 0.01 * size, far: 3 * size });
  sun.shadow.mapSize.set(2048, 2048); sun.shadow.radius = 6;
  scene.add(sun, sun.target);

  // the floor: a plane with a grid, a little under the scene
  const fw = fl.hi[0] - fl.lo[0], fh = fl.hi[1] - fl.lo[1];
  const floor = new T.Mesh(new T.PlaneGeometry(fw, fh), new T.MeshBasicMaterial({ color: S.floor }));  // flat, as in the video
  floor.position.set((fl.lo[0] + fl.hi[0]) / 2, (fl.lo[1] + fl.hi[1]) / 2, fl.z); floor.receiveShadow = true;
  scene.add(floor);
  const shadowOnly = new T.Mesh(new T.PlaneGeometry(fw, fh), new T.ShadowMaterial({ opacity: 0.18 }));
  shadowOnly.position.copy(floor.position); shadowOnly.position.z += size * 1e-4; shadowOnly.receiveShadow = true;
  scene.add(shadowOnly);
  const grid = [];
  for (let x = Math.ceil(fl.lo[0] / fl.step) * fl.step; x <= fl.hi[0] + 1e-9; x += fl.step) grid.push(x, fl.lo[1], fl.z, x, fl.hi[1], fl.z);
  for (let y = Math.ceil(fl.lo[1] / fl.step) * fl.step; y <= fl.hi[1] + 1e-9; y += fl.step) grid.push(fl.lo[0], y, fl.z, fl.hi[0], y, fl.z);
  const gridGeo = new T.BufferGeometry(); gridGeo.setAttribute("position", new T.BufferAttribute(new Float32Array(grid), 3));
  const gridLines = new T.LineSegments(gridGeo, new T.LineBasicMaterial({ color: S.grid }));
  gridLines.position.z = size * 2e-4; scene.add(gridLines);

  // obstacles: shaded spheres and their influence shells; a named obstacle's name labels its centre
  const shells = [], obstacleLabels = [];
  const named = (mesh, o) => {
    if (o.name === undefined) return;
    const el = document.createElement("div");
    el.className = "obstacle-label"; el.textContent = o.name; $("labels").append(el);
    obstacleLabels.push({ el, position: mesh.position.clone() });
  };
  for (const o of D.obstacles) {
    const r = o.radius > 0 ? o.radius : hw * 0.6;
    const s = new T.Mesh(new T.SphereGeometry(r, 48, 32), new T.MeshPhongMaterial({ color: S.obstacle, shininess: 40, specular: 0x555555 }));
    s.position.fromArray(o.center); s.castShadow = true; scene.add(s); named(s, o);
    if (o.influence > 0) {
      const sh = new T.Mesh(new T.SphereGeometry(o.radius + o.influence, 48, 24),
        new T.MeshBasicMaterial({ color: S.obstacle, transparent: true, opacity: 0.05, depthWrite: false }));
      const wire = new T.Mesh(new T.SphereGeometry(o.radius + o.influence, 16, 8),
        new T.MeshBasicMaterial({ color: S.obstacle, wireframe: true, transparent: true, opacity: 0.13, depthWrite: false }));
      sh.position.fromArray(o.center); wire.position.fromArray(o.center); scene.add(sh, wire); shells.push(sh, wire);
    }
  }
  // boxes (rotation: world-from-box, rows), capsule obstacles and cylinders (rotation: world-from-cylinder, rows,
  // the axis its z), shaded alike; their shells: the box grown by its influence, the capsule's radius grown by it,
  // the cylinder's radius and half length grown by it
  const obstacleMat = new T.MeshPhongMaterial({ color: S.obstacle, shininess: 40, specular: 0x555555 });
  const shellMats = [new T.MeshBasicMaterial({ color: S.obstacle, transparent: true, opacity: 0.05, depthWrite: false }),
    new T.MeshBasicMaterial({ color: S.obstacle, wireframe: true, transparent: true, opacity: 0.13, depthWrite: false })];
  const place = (mesh, position, quaternion) => { mesh.position.fromArray(position); mesh.quaternion.copy(quaternion); return mesh; };
  // a box's six faces in world coordinates (the bundle keeps no BoxGeometry): half edges h, rotation R (rows)
  const boxGeometry = (center, h, R) => {
    const pos = [], nor = [], idx = [];
    for (let axis = 0; axis < 3; axis++) for (const sign of [-1, 1]) {
      const u = (axis + 1) % 3, v = (axis + 2) % 3, base = pos.length / 3;
      for (const [su, sv] of [[-1, -1], [1, -1], [1, 1], [-1, 1]]) {
        const local = [0, 0, 0]; local[axis] = sign * h[axis]; local[u] = su * h[u]; local[v] = sv * h[v];
        for (let r = 0; r < 3; r++) {
          pos.push(center[r] + R[r][0] * local[0] + R[r][1] * local[1] + R[r][2] * local[2]);
          nor.push(sign * R[r][axis]);
        }
      }
      idx.push(...(sign > 0 ? [base, base + 1, base + 2, base, base + 2, base + 3] : [base, base + 2, base + 1, base, base + 3, base + 2]));
    }
    const g = new T.BufferGeometry();
    g.setAttribute("position", new T.BufferAttribute(new Float32Array(pos), 3));
    g.setAttribute("normal", new T.BufferAttribute(new Float32Array(nor), 3));
    g.setIndex(idx);
    return g;
  };
  for (const b of D.boxes || []) {
    const half = b.size.map((v) => v / 2);
    const solid = new T.Mesh(boxGeometry(b.center, half, b.rotation), obstacleMat);
    solid.castShadow = true; solid.receiveShadow = true; scene.add(solid); named(solid, b);
    if (b.influence > 0) {
      const grown = boxGeometry(b.center, half.map((v) => v + b.influence), b.rotation);
      for (const mat of shellMats) { const sh = new T.Mesh(grown, mat); scene.add(sh); shells.push(sh); }
    }
  }
  for (const c of D.obstacle_capsules || []) {
    const a = new T.Vector3().fromArray(c.from), e = new T.Vector3().fromArray(c.to);
    const axis = e.clone().sub(a), len = axis.length();
    const q = new T.Quaternion().setFromUnitVectors(new T.Vector3(0, 1, 0), len > 0 ? axis.clone().normalize() : new T.Vector3(0, 1, 0));
    const mid = a.clone().add(e).multiplyScalar(0.5).toArray();
    const solid = place(new T.Mesh(new T.CapsuleGeometry(c.radius, Math.max(len, 1e-9), 8, 24), obstacleMat), mid, q);
    solid.castShadow = true; scene.add(solid); named(solid, c);
    if (c.influence > 0) {
      for (const mat of shellMats) {
        const sh = place(new T.Mesh(new T.CapsuleGeometry(c.radius + c.influence, Math.max(len, 1e-9), 8, 16), mat), mid, q);
        scene.add(sh); shells.push(sh);
      }
    }
  }

  // the unit quaternion of a rotation matrix m (rows), Shepperd's way (the bundle keeps no Matrix4)
  const quaternionOf = (m) => {
    const trace = m[0][0] + m[1][1] + m[2][2];
    if (trace > 0) {
      const s = 0.5 / Math.sqrt(trace + 1);
      return new T.Quaternion((m[2][1] - m[1][2]) * s, (m[0][2] - m[2][0]) * s, (m[1][0] - m[0][1]) * s, 0.25 / s);
    }
    if (m[0][0] > m[1][1] && m[0][0] > m[2][2]) {
      const s = 2 * Math.sqrt(1 + m[0][0] - m[1][1] - m[2][2]);
      return new T.Quaternion(0.25 * s, (m[0][1] + m[1][0]) / s, (m[0][2] + m[2][0]) / s, (m[2][1] - m[1][2]) / s);
    }
    if (m[1][1] > m[2][2]) {
      const s = 2 * Math.sqrt(1 + m[1][1] - m[0][0] - m[2][2]);
      return new T.Quaternion((m[0][1] + m[1][0]) / s, 0.25 * s, (m[1][2] + m[2][1]) / s, (m[0][2] - m[2][0]) / s);
    }
    const s = 2 * Math.sqrt(1 + m[2][2] - m[0][0] - m[1][1]);
    return new T.Quaternion((m[0][2] + m[2][0]) / s, (m[1][2] + m[2][1]) / s, 0.25 * s, (m[1][0] - m[0][1]) / s);
  };
  for (const c of D.cylinders || []) {
    // three's cylinder stands along its y: turn y to the cylinder's axis (the rotation's third column)
    const R = c.rotation, q = quaternionOf(R.map((row) => [row[0], row[2], -row[1]]));
    const solid = place(new T.Mesh(new T.CylinderGeometry(c.radius, c.radius, c.length, 48), obstacleMat), c.center, q);
    solid.castShadow = true; solid.receiveShadow = true; scene.add(solid); named(solid, c);
    if (c.influence > 0) {
      for (const mat of shellMats) {
        const grown = new T.CylinderGeometry(c.radius + c.influence, c.radius + c.influence, c.length + 2 * c.influence, 32);
        const sh = place(new T.Mesh(grown, mat), c.center, q); scene.add(sh); shells.push(sh);
      }
    }
  }

  // the objects a run moves (pick and place): each in its own frame, placed every frame
  const carried = ((D.carried || {}).objects || []).map((o) => {
    const holder = new T.Group();
    let solid;
    if (o.kind === "box") solid = new T.Mesh(boxGeometry([0, 0, 0], o.size.map((v) => v / 2), [[1, 0, 0], [0, 1, 0], [0, 0, 1]]), obstacleMat);
    else if (o.kind === "sphere") solid = new T.Mesh(new T.SphereGeometry(o.radius, 24, 16), obstacleMat);
    else if (o.kind === "capsule") {  // three's capsule stands along its y: turn y to x
      solid = new T.Mesh(new T.CapsuleGeometry(o.radius, Math.max(o.length, 1e-9), 8, 24), obstacleMat);
      solid.rotation.z = -Math.PI / 2;
    } else {  // a cylinder: y to z
      solid = new T.Mesh(new T.CylinderGeometry(o.radius, o.radius, o.length, 48), obstacleMat);
      solid.rotation.x = Math.PI / 2;
    }
    solid.castShadow = true; solid.receiveShadow = true; holder.add(solid); scene.add(holder);
    return holder;
  });
  function placeCarried(f) {
    const Q = D.carried.poses, K = carried.length;
    carried.forEach((h, k) => {
      const o = (f * K + k) * 7;
      h.position.set(Q[o], Q[o + 1], Q[o + 2]);
      h.quaternion.set(Q[o + 4], Q[o + 5], Q[o + 6], Q[o + 3]);  // three.js: x, y, z, w
    });
  }

  // goals: small spheres coloured by their state at the frame
  const goalR = Math.max(hw * 1.2, size * 0.008);
  // (and faintly through whatever hides them, as the video shows a goal behind a sphere)
  const goalGeo = new T.SphereGeometry(goalR, 24, 16);
  const goalMeshes = D.goals.map((g) => {
    const m = new T.Mesh(goalGeo, new T.MeshLambertMaterial({ color: S.goals.pending }));
    const ghost = new T.Mesh(goalGeo, new T.MeshBasicMaterial({ color: S.goals.pending, transparent: true, opacity: 0.45, depthTest: false, depthWrite: false }));
    ghost.renderOrder = 10; m.userData.ghost = ghost;
    m.position.fromArray(g.position); ghost.position.fromArray(g.position); scene.add(m, ghost); return m;
  });
  const GOAL_PX = 6;  // a goal's marker keeps this radius on screen at any zoom: it never hides the wrist
  // and a faint line drops from each goal to the floor, to show where it stands
  const drops = D.goals.map((g) => {
    const geo = new T.BufferGeometry();
    geo.setAttribute("position", new T.BufferAttribute(new Float32Array([...g.position, g.position[0], g.position[1], fl.z]), 3));
    const line = new T.Line(geo, new T.LineBasicMaterial({ color: S.goals.pending, transparent: true, opacity: 0.45 }));
    scene.add(line); return line;
  });

  // orientations (only in a run with an oriented goal): the tool frame's x, y, z axes at the tip
  // in red, green, blue, and each such goal's triad faintly (a tool-axis goal: its z alone)
  const O = D.orientation, toolAxes = [];
  function segment(color, opacity) {
    const g = new T.BufferGeometry();
    g.setAttribute("position", new T.BufferAttribute(new Float32Array(6), 3));
    const l = new T.Line(g, new T.LineBasicMaterial({ color, transparent: opacity < 1, opacity }));
    l.frustumCulled = false; scene.add(l); return l;
  }
  function setSegment(line, from, dir, len) {
    const p = line.geometry.attributes.position;
    p.setXYZ(0, from[0], from[1], from[2]);
    p.setXYZ(1, from[0] + len * dir[0], from[1] + len * dir[1], from[2] + len * dir[2]);
    p.needsUpdate = true;
  }
  if (O) {
    for (let i = 0; i < 3; i++) toolAxes.push(segment(O.colors[i], 1));
    D.goals.forEach((g) => {
      if (g.rotation) for (let i = 0; i < 3; i++) setSegment(segment(O.colors[i], 0.45), g.position, [g.rotation[0][i], g.rotation[1][i], g.rotation[2][i]], O.triad);
      else if (g.tool_axis) setSegment(segment(O.colors[2], 0.45), g.position, g.tool_axis, O.triad);
    });
  }
  const UNIT = [new T.Vector3(1, 0, 0), new T.Vector3(0, 1, 0), new T.Vector3(0, 0, 1)], q = new T.Quaternion(), u = new T.Vector3();
  function toolFrame(f) {
    const Q = O.quaternion_wxyz, o = (f * P + N) * 3;
    q.set(Q[f * 4 + 1], Q[f * 4 + 2], Q[f * 4 + 3], Q[f * 4]);  // three.js: x, y, z, w
    const tip = [D.points[o], D.points[o + 1], D.points[o + 2]];
    for (let i = 0; i < 3; i++) { u.copy(UNIT[i]).applyQuaternion(q); setSegment(toolAxes[i], tip, [u.x, u.y, u.z], O.triad); }
  }

  // the arm: its collision capsules (the shapes clearance is measured on), a disc per joint, the base
  const armMat = new T.MeshPhongMaterial({ color: S.arm, shininess: 30 });
  const nearMat = new T.MeshPhongMaterial({ color: S.self_near || S.arm, shininess: 30 });  // a pair of the arm's own links close together
  const jointMat = new T.MeshPhongMaterial({ color: S.joint, shininess: 60 });
  const C = D.capsules.radius.length, E = D.capsules.ends;  // ends: F x C x 2 x 3
  const links = D.capsules.radius.map((r, i) => {
    const o = i * 6, len = Math.hypot(E[o + 3] - E[o], E[o + 4] - E[o + 1], E[o + 5] - E[o + 2]);
    const c = new T.Mesh(new T.CapsuleGeometry(Math.max(r, 1e-9), Math.max(len, 1e-9), 6, 20), armMat);
    c.castShadow = true; scene.add(c); return c;
  });
  const joints = [];
  for (let i = 0; i < N; i++) {
    const b = new T.Mesh(new T.SphereGeometry(hw * S.joint_scale, 24, 16), jointMat);
    b.castShadow = true; scene.add(b); joints.push(b);
  }
  // the robot's meshes (its URDF's visuals), when the run has them: each carrier's triangles once, moved every frame
  const meshGroups = [];
  if (D.meshes) {
    const linear = (c) => (c <= 0.04045 ? c / 12.92 : Math.pow((c + 0.055) / 1.055, 2.4));  // the data's sRGB, as three.js lights
    const meshMat = () => new T.MeshPhongMaterial({ vertexColors: true, shininess: 40 });  // one a group: a near pair tints it
    for (const g of D.meshes.groups) {
      const geo = new T.BufferGeometry();
      geo.setAttribute("position", new T.BufferAttribute(new Float32Array(g.positions), 3));
      geo.setAttribute("color", new T.BufferAttribute(new Float32Array(g.colors.map(linear)), 3));
      geo.setIndex(g.indices);
      geo.computeVertexNormals();
      const m = new T.Mesh(geo, meshMat());
      m.castShadow = true;
      const holder = new T.Group();
      holder.add(m); scene.add(holder);
      meshGroups.push({ holder, mesh: m, slot: D.meshes.carriers.indexOf(g.carrier), slide: g.slide || null });
    }
  }
  api.fingers = () => meshGroups.filter((g) => g.slide).map((g) => {  // each finger's vertex centroid in the world (the tests')
    const p = g.mesh.geometry.getAttribute("position"), c = new T.Vector3();
    for (let i = 0; i < p.count; i++) c.add(new T.Vector3(p.getX(i), p.getY(i), p.getZ(i)));
    g.mesh.updateWorldMatrix(true, false);
    return g.mesh.localToWorld(c.multiplyScalar(1 / p.count)).toArray();
  });
  const base = new T.Mesh(new T.CylinderGeometry(hw * S.base_scale, hw * S.base_scale, 2 * hw, 32), new T.MeshPhongMaterial({ color: S.base }));
  base.rotation.x = Math.PI / 2; base.position.set(D.arm.base[0], D.arm.base[1], D.arm.base[2] - hw); base.castShadow = true;
  scene.add(base);

  // the tip's path: all tips in one buffer, drawn up to the frame
  const trailPos = new Float32Array(F * 3);
  for (let f = 0; f < F; f++) for (let k = 0; k < 3; k++) trailPos[f * 3 + k] = D.points[(f * P + N) * 3 + k];
  const trailGeo = new T.BufferGeometry(); trailGeo.setAttribute("position", new T.BufferAttribute(trailPos, 3));
  const trail = new T.Line(trailGeo, new T.LineBasicMaterial({ color: S.trail }));
  trail.frustumCulled = false; scene.add(trail);
  $("trail").checked = D.view.trail; trail.visible = D.view.trail;

  // path goals, as in the video: the ink (the pen-down path from 0 to the farthest path_s reached on
  // the goal's frames so far) and, while the goal is the frame's, the pen-down path still ahead,
  // faint and dashed; pen-up travel is never drawn
  const PA = D.paths, pathViews = [];
  // a strip: pieces [s0, s1] of a polyline from a to b, drawn as line segments or (ribbon: the ink) as
  // flat quads half-width w wide across each piece, square to the path's normal n; a range of arc
  // lengths of it is shown
  function strip(pieces, material, ribbon) {
    const V = ribbon ? 6 : 2, pos = new Float32Array(pieces.length * V * 3), geo = new T.BufferGeometry();
    geo.setAttribute("position", new T.BufferAttribute(pos, 3));
    const line = ribbon ? new T.Mesh(geo, material) : new T.LineSegments(geo, material);
    line.frustumCulled = false; scene.add(line);
    const st = { line, pieces, ribbon, V, touched: [] };
    pieces.forEach((c, i) => placePiece(st, i, c.a, c.b));
    return st;
  }
  const sub3 = (x, y) => [x[0] - y[0], x[1] - y[1], x[2] - y[2]];
  function placePiece(st, i, a, b) {  // piece i of the strip drawn from a to b
    const p = st.line.geometry.attributes.position;
    if (!st.ribbon) { p.setXYZ(2 * i, ...a); p.setXYZ(2 * i + 1, ...b); return; }
    const c = st.pieces[i], d = sub3(b, a), L = Math.hypot(...d) || 1, h = c.h;
    const n = c.n, w = [(d[1] * n[2] - d[2] * n[1]) / L * h, (d[2] * n[0] - d[0] * n[2]) / L * h, (d[0] * n[1] - d[1] * n[0]) / L * h];
    const a0 = a.map((v, k) => v - d[k] / L * h), b0 = b.map((v, k) => v + d[k] / L * h);  // square ends: corners close
    const q = [a0.map((v, k) => v + w[k]), a0.map((v, k) => v - w[k]), b0.map((v, k) => v - w[k]), b0.map((v, k) => v + w[k])];
    [q[0], q[1], q[2], q[0], q[2], q[3]].forEach((v, k) => p.setXYZ(6 * i + k, ...v));
  }
  function showStrip(st, lo, hi) {  // the part of the strip between arc lengths lo and hi
    const P = st.pieces;
    for (const i of st.touched) placePiece(st, i, P[i].a, P[i].b);
    st.touched = [];
    let first = 0, last = P.length;  // pieces first .. last-1 meet (lo, hi)
    while (first < P.length && P[first].s1 <= lo) first++;
    while (last > first && P[last - 1].s0 >= hi) last--;
    const cut = (c, s) => { const t = clamp((s - c.s0) / Math.max(c.s1 - c.s0, 1e-300), 0, 1); return [0, 1, 2].map((k) => c.a[k] + t * (c.b[k] - c.a[k])); };
    for (const i of new Set([first, last - 1])) {
      if (i < first || i >= last || (P[i].s0 >= lo && P[i].s1 <= hi)) continue;
      placePiece(st, i, P[i].s0 < lo ? cut(P[i], lo) : P[i].a, P[i].s1 > hi ? cut(P[i], hi) : P[i].b);
      st.touched.push(i);
    }
    st.line.geometry.attributes.position.needsUpdate = true;
    st.line.geometry.setDrawRange(st.V * first, st.V * Math.max(last - first, 0));
  }
  if (PA) {
    const inkMat = new T.MeshBasicMaterial({ color: PA.ink, side: T.DoubleSide, polygonOffset: true, polygonOffsetFactor: -1, polygonOffsetUnits: -4 });
    const aheadMat = new T.LineBasicMaterial({ color: PA.ink, transparent: true, opacity: PA.ahead_opacity, depthWrite: false });
    for (const g of PA.goals) {
      const at = (i) => [g.points[i * 3], g.points[i * 3 + 1], g.points[i * 3 + 2]], h = PA.width / 2;
      const ink = [];  // the pen-down pieces between samples
      for (let i = 0; i + 1 < g.s.length; i++) if (g.ink[i]) ink.push({ s0: g.s[i], s1: g.s[i + 1], a: at(i), b: at(i + 1), n: g.normal, h });
      const length = g.s[g.s.length - 1], dash = size / 160, period = dash * 5 / 3, dashes = [];  // as the video's 3:2
      for (const c of ink) {
        for (let k = Math.floor(c.s0 / period); k * period < c.s1; k++) {
          const s0 = Math.max(c.s0, k * period), s1 = Math.min(c.s1, k * period + dash);
          if (s1 <= s0) continue;
          const t0 = (s0 - c.s0) / Math.max(c.s1 - c.s0, 1e-300), t1 = (s1 - c.s0) / Math.max(c.s1 - c.s0, 1e-300);
          dashes.push({ s0, s1, a: [0, 1, 2].map((j) => c.a[j] + t0 * (c.b[j] - c.a[j])), b: [0, 1, 2].map((j) => c.a[j] + t1 * (c.b[j] - c.a[j])) });
        }
      }
      const done = new Float64Array(F);  // the farthest arc length reached on the goal's frames up to each frame
      let most = 0;
      for (let f = 0; f < F; f++) {
        const s = PA.path_s[f];
        if (D.goal[f] === g.goal && s !== null) most = Math.max(most, s);
        done[f] = most;
      }
      pathViews.push({ goal: g.goal, length, done, ink: strip(ink, inkMat, true), ahead: strip(dashes, aheadMat, false) });
    }
  }
  function drawPaths(f) {
    for (const v of pathViews) {
      showStrip(v.ink, 0, v.done[f]);
      v.ahead.line.visible = D.goal[f] === v.goal;
      if (v.ahead.line.visible) showStrip(v.ahead, v.done[f], Infinity);
    }
  }
  api.pathDone = (k) => pathViews.map((v) => v.done[k === undefined ? api.frame : k]);

  const Y = new T.Vector3(0, 1, 0), a = new T.Vector3(), b = new T.Vector3(), d = new T.Vector3();
  function pose(f) {
    const p = D.points, o = f * P * 3;
    for (let i = 0; i < N; i++) joints[i].position.set(p[o + i * 3], p[o + i * 3 + 1], p[o + i * 3 + 2]);
    for (let i = 0; i < C; i++) {
      const e = (f * C + i) * 6;
      a.set(E[e], E[e + 1], E[e + 2]);
      b.set(E[e + 3], E[e + 4], E[e + 5]);
      links[i].position.addVectors(a, b).multiplyScalar(0.5);
      d.subVectors(b, a);
      if (d.lengthSq() > 0) links[i].quaternion.setFromUnitVectors(Y, d.normalize());
      links[i].material = armMat;
    }
    if (D.capsules.near) for (const i of D.capsules.near[f]) links[i].material = nearMat;
    if (D.meshes && D.capsules.near) {  // a meshed link in a close pair is tinted as its capsule is
      meshGroups.forEach((g) => g.mesh.material.color.setRGB(1, 1, 1));
      for (const i of D.capsules.near[f]) {
        const k = D.meshes.capsule_group[i];
        if (k >= 0) meshGroups[k].mesh.material.color.set(S.self_near);
      }
    }
    if (D.meshes) {
      const K = D.meshes.carriers.length, M = D.meshes.frames;
      for (const g of meshGroups) {
        if (g.slot < 0) continue;  // links that never move
        const o = (f * K + g.slot) * 7;
        g.holder.position.set(M[o], M[o + 1], M[o + 2]);
        g.holder.quaternion.set(M[o + 4], M[o + 5], M[o + 6], M[o + 3]);  // three.js: x, y, z, w
        if (g.slide && D.meshes.fingers) {  // a finger: slid in its carrier's frame by the gripper's value
          const v = D.meshes.fingers[f];
          g.mesh.position.set(g.slide[0] * v, g.slide[1] * v, g.slide[2] * v);
        }
      }
    }
    trailGeo.setDrawRange(0, f + 1);
    drawPaths(f);
    if (O) toolFrame(f);
    if (carried.length) placeCarried(f);
  }

  // ---- the camera: the video's view, front, side, top; orbit, pan and zoom ----------
  const controls = new T.OrbitControls(camera, renderer ? renderer.domElement : view);
  controls.enableDamping = false;
  controls.addEventListener("change", () => { st.dirty = true; });
  let halfHeight = size;  // half the frustum's height at zoom 1, world units
  const fitPoints = [[fl.lo[0], fl.lo[1], fl.z, 0], [fl.hi[0], fl.lo[1], fl.z, 0], [fl.lo[0], fl.hi[1], fl.z, 0], [fl.hi[0], fl.hi[1], fl.z, 0],
    [D.arm.base[0], D.arm.base[1], D.arm.base[2] - 2 * hw, hw * S.base_scale]];
  D.obstacles.forEach((o) => fitPoints.push([...o.center, o.radius + o.influence]));
  (D.boxes || []).forEach((b) => fitPoints.push([...b.center, 0.5 * Math.hypot(...b.size) + b.influence]));
  (D.obstacle_capsules || []).forEach((c) => { fitPoints.push([...c.from, c.radius + c.influence]); fitPoints.push([...c.to, c.radius + c.influence]); });
  (D.cylinders || []).forEach((c) => fitPoints.push([...c.center, Math.hypot(c.radius, c.length / 2) + c.influence]));
  D.goals.forEach((g) => fitPoints.push([...g.position, goalR * 3]));
  if (D.paths) for (const g of D.paths.goals) for (let i = 0; i < g.points.length; i += 3) fitPoints.push([g.points[i], g.points[i + 1], g.points[i + 2], 0]);
  if (D.view.bounds) for (const x of D.view.bounds[0]) for (const y of D.view.bounds[1]) for (const z of D.view.bounds[2]) fitPoints.push([x, y, z, 0]);
  const VIEWS = {
    video: [D.view.elevation, D.view.azimuth],
    front: [0, -90],
    side: [0, 0],
    top: [90, -90],
  };
  function setView(name) {
    const va = VIEWS[name] || VIEWS.video;
    const e = clamp(va[0], -89.95, 89.95) * Math.PI / 180, az = va[1] * Math.PI / 180;
    const toward = new T.Vector3(Math.cos(e) * Math.cos(az), Math.cos(e) * Math.sin(az), Math.sin(e));
    const right = new T.Vector3(-Math.sin(az), Math.cos(az), 0), up = new T.Vector3().crossVectors(toward, right);
    // fit what the video fits: every joint of every frame, the spheres, the goals, the floor
    let x0 = Infinity, x1 = -Infinity, y0 = Infinity, y1 = -Infinity;
    const fit = (x, y, z, r) => {
      const u = x * right.x + y * right.y + z * right.z, v = x * up.x + y * up.y + z * up.z;
      x0 = Math.min(x0, u - r); x1 = Math.max(x1, u + r); y0 = Math.min(y0, v - r); y1 = Math.max(y1, v + r);
    };
    for (const q of fitPoints) fit(q[0], q[1], q[2], q[3]);
    const pts = D.points;
    if (!D.view.bounds) for (let i = 0; i < pts.length; i += 3) fit(pts[i], pts[i + 1], pts[i + 2], hw);
    // into the view less room for the caption above and the help line below (pixels)
    const W = Math.max(view.clientWidth, 1), H = Math.max(view.clientHeight, 1), MT = 46, MB = 22, MX = 12;
    const usableH = Math.max(H - MT - MB, H * 0.5), usableW = Math.max(W - 2 * MX, W * 0.5);
    const ppu = Math.min(usableH / Math.max(y1 - y0, 1e-9), usableW / Math.max(x1 - x0, 1e-9)) / 1.03;
    halfHeight = H / 2 / ppu;
    const shift = (MT - MB) / 2 / ppu;  // the content's centre sits this far below the view's
    const target = center.clone().sub(right.clone().multiplyScalar(center.dot(right) - (x0 + x1) / 2))
      .sub(up.clone().multiplyScalar(center.dot(up) - (y0 + y1) / 2 - shift));
    controls.target.copy(target);
    camera.position.copy(target).addScaledVector(toward, size * 4);
    camera.zoom = 1;
    frustum();
    camera.lookAt(target);
    controls.update();
    st.dirty = true;
  }
  function viewAspect() { return Math.max(view.clientWidth, 1) / Math.max(view.clientHeight, 1); }
  function frustum() {
    const aspect = viewAspect();
    camera.left = -halfHeight * aspect; camera.right = halfHeight * aspect; camera.top = halfHeight; camera.bottom = -halfHeight;
    camera.updateProjectionMatrix();
  }
  document.querySelectorAll("#views button").forEach((btn) => btn.addEventListener("click", () => { setView(btn.dataset.view); btn.blur(); }));

  // ---- the plot: joint angles and the goal distance over time -------------------------
  const plot = $("plot"), pc = plot.getContext("2d"), PL = 48, PR = 52, PT = 10, PB = 22;
  let plotCache = null, amin = Infinity, amax = -Infinity, dmax = 0;
  for (let i = 0; i < F * N; i++) { amin = Math.min(amin, D.angles_deg[i]); amax = Math.max(amax, D.angles_deg[i]); }
  for (let f = 0; f < F; f++) dmax = Math.max(dmax, D.distance[f]);
  if (amax - amin < 1) { amin -= 1; amax += 1; }
  if (dmax <= 0) dmax = 1;
  const plotX = (f, w) => PL + (w - PL - PR) * f / Math.max(F - 1, 1);
  function drawPlotBase() {
    const r = window.devicePixelRatio || 1, w = plot.clientWidth, h = plot.clientHeight;
    plotCache = document.createElement("canvas");
    plotCache.width = Math.max(1, Math.round(w * r)); plotCache.height = Math.max(1, Math.round(h * r));
    const c = plotCache.getContext("2d"); c.setTransform(r, 0, 0, r, 0, 0);
    c.fillStyle = "#fff"; c.fillRect(0, 0, w, h);
    const Ya = (v) => PT + (h - PT - PB) * (amax - v) / (amax - amin), Yd = (v) => PT + (h - PT - PB) * (1 - v / dmax);
    const planning = D.activities.indexOf("planning");  // frames that follow a planned path: shaded
    if (planning >= 0) {
      c.fillStyle = "#eef2fb";
      for (let f = 0; f < F; f++) if (D.activity[f] === planning) c.fillRect(plotX(f - 0.5, w), PT, Math.max((w - PL - PR) / Math.max(F - 1, 1), 1), h - PT - PB);
    }
    c.font = "11px system-ui, 'DejaVu Sans', sans-serif"; c.fillStyle = "#555"; c.strokeStyle = "#e4e5ea";
    for (let f = 1; f < F; f++) if (D.goal[f] !== D.goal[f - 1]) { c.beginPath(); c.moveTo(plotX(f, w), PT); c.lineTo(plotX(f, w), h - PB); c.stroke(); }
    c.strokeStyle = "#c8cad2"; c.beginPath(); c.moveTo(PL, PT); c.lineTo(PL, h - PB); c.lineTo(w - PR, h - PB); c.lineTo(w - PR, PT); c.stroke();
    if (amin < 0 && amax > 0) { c.setLineDash([2, 3]); c.beginPath(); c.moveTo(PL, Ya(0)); c.lineTo(w - PR, Ya(0)); c.stroke(); c.setLineDash([]); }
    c.textAlign = "right"; c.fillText(amax.toFixed(0) + "°", PL - 4, PT + 9); c.fillText(amin.toFixed(0) + "°", PL - 4, h - PB);
    c.textAlign = "left"; c.fillText(dmax.toPrecision(3), w - PR + 4, PT + 9); c.fillText("0", w - PR + 4, h - PB);
    c.fillText("0 s", PL, h - 6); c.textAlign = "right"; c.fillText((RUN_LAST / D.fps).toFixed(2) + " s", w - PR, h - 6);
    const step = Math.max(1, Math.floor(F / Math.max(w * 2, 1)));
    for (let j = 0; j < N; j++) {
      c.strokeStyle = PLOT_COLORS[j % PLOT_COLORS.length]; c.lineWidth = 1.3; c.beginPath();
      for (let f = 0; f < F; f += step) { const x = plotX(f, w), y = Ya(D.angles_deg[f * N + j]); f ? c.lineTo(x, y) : c.moveTo(x, y); }
      c.stroke();
    }
    c.strokeStyle = "#111"; c.lineWidth = 1.4; c.setLineDash([5, 3]); c.beginPath();
    for (let f = 0; f < F; f += step) { const x = plotX(f, w), y = Yd(D.distance[f]); f ? c.lineTo(x, y) : c.moveTo(x, y); }
    c.stroke(); c.setLineDash([]);
    c.textAlign = "center"; c.fillStyle = "#111";
    const legend = w < 560 ? "angles (left)  - - distance (right)" : "joint angles (left, colours as in the table)   - - goal distance (right)";
    c.fillText(legend + (planning >= 0 && w >= 560 ? "   shaded: planning" : ""), (PL + w - PR) / 2, h - 6);
  }
  function drawPlot(f) {
    const r = window.devicePixelRatio || 1, w = plot.clientWidth, h = plot.clientHeight;
    if (!plotCache || plotCache.width !== Math.max(1, Math.round(w * r)) || plotCache.height !== Math.max(1, Math.round(h * r))) {
      plot.width = Math.max(1, Math.round(w * r)); plot.height = Math.max(1, Math.round(h * r)); drawPlotBase();
    }
    pc.setTransform(1, 0, 0, 1, 0, 0); pc.drawImage(plotCache, 0, 0);
    pc.setTransform(r, 0, 0, r, 0, 0); pc.strokeStyle = "#000"; pc.lineWidth = 1.5;
    pc.beginPath(); pc.moveTo(plotX(f, w), PT - 4); pc.lineTo(plotX(f, w), h - PB + 4); pc.stroke();
  }
  function seekFromPlot(ev) {
    const rect = plot.getBoundingClientRect(), w = rect.width;
    setFrame(Math.round((ev.clientX - rect.left - PL) / Math.max(w - PL - PR, 1) * (F - 1)));
  }
  let plotDrag = false;
  plot.addEventListener("pointerdown", (ev) => { plotDrag = true; plot.setPointerCapture(ev.pointerId); seekFromPlot(ev); });
  plot.addEventListener("pointermove", (ev) => { if (plotDrag) seekFromPlot(ev); });
  plot.addEventListener("pointerup", () => { plotDrag = false; });

  // ---- showing a frame ------------------------------------------------------------
  function show() {
    const f = st.frame;
    if (st.playing !== st.shownPlaying) {
      st.shownPlaying = st.playing;
      const playBtn = $("play");
      playBtn.textContent = st.playing ? "Pause" : "Play";
      playBtn.setAttribute("aria-label", st.playing ? "pause" : "play");
    }
    if (f === st.shown) return;
    st.shown = f;
    slider.value = String(f);
    $("frame").textContent = String(runFrame(f));
    $("time").textContent = (runFrame(f) / D.fps).toFixed(2);
    document.body.dataset.frame = String(f);
    const k = D.goal[f], ngoals = D.goals.length;
    $("goal").textContent = ngoals ? `${k} (of 0-${ngoals - 1})` : "none";
    $("distance").textContent = fixed(D.distance[f], 3) + (O && O.angle_deg[f] !== null ? `, angle ${O.angle_deg[f].toFixed(1)}°` : "");
    $("clearance").textContent = fixed(D.clearance[f], 3);
    $("state").textContent = D.activities[D.activity[f]];
    for (let j = 0; j < N; j++) angleCells[j].textContent = D.angles_deg[f * N + j].toFixed(2);
    const states = goalStates(f);
    states.forEach((s, i) => {
      goalMeshes[i].material.color.set(S.goals[s]); goalMeshes[i].userData.ghost.material.color.set(S.goals[s]);
      drops[i].material.color.set(S.goals[s]);
      labels[i].dataset.state = s; labels[i].style.color = S.goals[s];
    });
    pose(f);
    drawPlot(f);
    st.dirty = true;
  }

  // ---- controls ---------------------------------------------------------------------
  $("play").addEventListener("click", () => (st.playing ? pause() : play()));
  $("speed").addEventListener("change", (ev) => setSpeed(ev.target.value));
  slider.addEventListener("input", () => setFrame(slider.value));
  $("shells").addEventListener("change", (ev) => { shells.forEach((s) => { s.visible = ev.target.checked; }); st.dirty = true; });
  $("trail").addEventListener("change", (ev) => { trail.visible = ev.target.checked; st.dirty = true; });
  // with meshes, the capsules alone are toggled (the mesh shows the joints and the base)
  const uncovered = new Set(D.meshes ? D.meshes.uncovered : []);  // capsules of links without a mesh: always shown
  const robotMeshes = !!(D.meshes && D.meshes.robot);  // the meshes draw the robot (not only the furniture)
  const showCapsules = (on) => { links.forEach((c, i) => { c.visible = on || uncovered.has(i); }); joints.forEach((j) => { j.visible = !robotMeshes; }); base.visible = !robotMeshes; };
  if (robotMeshes) {
    const both = D.meshes.look === "both";  // render.robot: the capsules translucent over the meshes
    if (both) for (const m of [armMat, nearMat]) { m.transparent = true; m.opacity = 0.35; m.depthWrite = false; }
    showCapsules(both);  // else the robot as it looks; the capsules (what clearance is measured on) on demand
    $("capsules").checked = both;
    $("capsules").addEventListener("change", (ev) => { showCapsules(ev.target.checked); st.dirty = true; });
  } else $("capsules").parentElement.hidden = true;
  function step(by) { if (st.playing) pause(); setFrame(st.frame + by); }
  window.addEventListener("keydown", (ev) => {
    const tag = ev.target && ev.target.tagName;
    if (tag === "SELECT" || ev.ctrlKey || ev.metaKey || ev.altKey) return;
    if (ev.key === " " || ev.key === "Spacebar") {
      ev.preventDefault();
      if (!ev.repeat) (st.playing ? pause() : play());
    } else if (ev.key === "ArrowRight" || ev.key === "ArrowUp") {
      ev.preventDefault(); step(1);  // preventDefault: a focused slider does not step as well
    } else if (ev.key === "ArrowLeft" || ev.key === "ArrowDown") {
      ev.preventDefault(); step(-1);
    }
  });
  // Space on a focused button or box would also click it on keyup: play/pause is all it does here
  window.addEventListener("keyup", (ev) => {
    const t = ev.target;
    if (ev.key === " " && t && (t.tagName === "BUTTON" || (t.tagName === "INPUT" && t.type === "checkbox"))) ev.preventDefault();
  });

  // ---- drawing ----------------------------------------------------------------------
  const tmp = new T.Vector3();
  function scaleGoals() {  // GOAL_PX pixels of radius: world units per pixel times GOAL_PX, over the sphere's radius
    const scale = GOAL_PX * (camera.top - camera.bottom) / camera.zoom / Math.max(view.clientHeight, 1) / goalR;
    goalMeshes.forEach((m) => { m.scale.setScalar(scale); m.userData.ghost.scale.setScalar(scale); });
  }
  function placeLabels() {
    const w = view.clientWidth, h = view.clientHeight;
    goalMeshes.forEach((m, i) => {
      tmp.copy(m.position).project(camera);
      labels[i].style.left = ((tmp.x + 1) / 2 * w).toFixed(1) + "px";
      labels[i].style.top = ((1 - tmp.y) / 2 * h).toFixed(1) + "px";
    });
    obstacleLabels.forEach(({ el, position }) => {
      tmp.copy(position).project(camera);
      el.style.left = ((tmp.x + 1) / 2 * w).toFixed(1) + "px";
      el.style.top = ((1 - tmp.y) / 2 * h).toFixed(1) + "px";
    });
  }
  function resize() {
    if (renderer) renderer.setSize(view.clientWidth, view.clientHeight, false);
    frustum(); drawPlot(st.frame); st.dirty = true;
  }
  function loop(now) {
    sync(now);
    show();
    if (st.dirty && renderer) {
      scaleGoals(); renderer.render(scene, camera); placeLabels(); st.drawn++;
    }
    st.dirty = false;
    if (renderer) waiters.splice(0).forEach((resolve) => resolve(st.drawn));
    requestAnimationFrame(loop);
  }
  if (renderer) {
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.shadowMap.enabled = true; renderer.shadowMap.type = T.PCFShadowMap;
    renderer.domElement.tabIndex = 0;
    view.prepend(renderer.domElement);
    api.webgl = true;
  }
  window.addEventListener("resize", resize);
  resize();
  setView("video");
  show();
  api.ready = true;
  requestAnimationFrame(loop);
})();
