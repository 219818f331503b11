// rigidae's run viewer (inlined into the page by tools/view_run.py).
//
// Data (view_run.py): geometry (app/scene_geometry.cpp: bodies with their
// shapes in body frames, joints with their points) and runs, each with times
// and frames: per frame, per body x, y, z (the body frame's origin in space)
// and qw, qx, qy, qz (R_WB, scalar first); forces: per frame, per joint in
// force_joints, the reaction force (N, space frame) on the body the joint's
// point is in. A shape's point x_V is at x + R (position + R_BV x_V).
// The address may hold #t=SECONDS: the page then shows that time, paused.

const MARKER_COLOUR = 0xd4a000;
const COLOURS = [0x4e79a7, 0xf28e2b, 0x59a14f, 0xe15759, 0x76b7b2, 0xedc948, 0xb07aa1, 0xff9da7, 0x9c755f];

export function start(THREE, data) {
  const G = data.geometry, runs = data.runs;
  const extent = Math.max(G.extent || 1, 1e-6);
  const view = document.getElementById("view");
  const renderer = new THREE.WebGLRenderer({antialias: true, preserveDrawingBuffer: true});
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  view.appendChild(renderer.domElement);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xfafafa);
  scene.add(new THREE.AmbientLight(0xffffff, 0.55));
  const sun = new THREE.DirectionalLight(0xffffff, 1.6);
  sun.position.set(1, -2, 3);
  scene.add(sun);
  const camera = new THREE.PerspectiveCamera(40, 1, extent * 1e-3, extent * 1e3);
  camera.up.set(0, 0, 1);

  // Where each run's bodies go: the span of all centres of mass decides the
  // view (along the axis the motion spans least) and the runs' spacing.
  const quat = (q) => new THREE.Quaternion(q[1], q[2], q[3], q[0]);
  // Each run's centres of mass, per body and frame (the trails), in space.
  const paths = runs.map((run) => G.bodies.map((b, i) => {
    const c = new THREE.Vector3(...b.center_of_mass), pts = new Float32Array(3 * run.frames.length);
    run.frames.forEach((fr, f) => {
      const p = c.clone().applyQuaternion(quat(fr.slice(7 * i + 3, 7 * i + 7)));
      pts[3 * f] = fr[7 * i] + p.x, pts[3 * f + 1] = fr[7 * i + 1] + p.y, pts[3 * f + 2] = fr[7 * i + 2] + p.z;
    });
    return pts;
  }));
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (const run of paths)
    for (const pts of run)
      for (let a = 0; a < pts.length; ++a) {
        lo[a % 3] = Math.min(lo[a % 3], pts[a]);
        hi[a % 3] = Math.max(hi[a % 3], pts[a]);
      }
  for (const j of G.joints)  // a ground point (a top's fixed point) is in the picture too
    if (j.body < 0 || G.schema_version === 1)
      for (let i = 0; i < 3; ++i) lo[i] = Math.min(lo[i], 0), hi[i] = Math.max(hi[i], 0);
  const pad = 0.5 * extent;
  const span = [0, 1, 2].map((i) => hi[i] - lo[i] + pad);
  const depth = [0, 1, 2].reduce((a, i) => (span[i] < span[a] ? i : a), 0);
  const side = depth === 0 ? 1 : 0;  // runs side by side along this axis
  const step = span[side] + 0.25 * extent;
  const centre = new THREE.Vector3((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2);

  const shapeGeometry = (v) => {
    let g;
    if (v.shape === "box") g = new THREE.BoxGeometry(v.size[0], v.size[1], v.size[2]);
    else if (v.shape === "sphere") g = new THREE.SphereGeometry(v.radius, 24, 16);
    else if (v.shape === "ellipsoid") {
      g = new THREE.SphereGeometry(1, 32, 16);
      g.scale(v.semi_axes[0], v.semi_axes[1], v.semi_axes[2]);
    } else if (v.shape === "cylinder") g = new THREE.CylinderGeometry(v.radius, v.radius, v.length, 24).rotateX(Math.PI / 2);
    else if (v.shape === "capsule") g = new THREE.CapsuleGeometry(v.radius, v.length, 8, 24).rotateX(Math.PI / 2);
    else g = new THREE.SphereGeometry(0.01 * extent);
    return g;
  };
  // A run's name drawn above its copy of the mechanism (a compare's runs side
  // by side look alike): text on a canvas, a sprite that always faces the camera.
  const nameTag = (text) => {
    const canvas = document.createElement("canvas"), px = 48;
    const ctx = canvas.getContext("2d");
    ctx.font = `${px}px sans-serif`;
    canvas.width = Math.ceil(ctx.measureText(text).width) + px, canvas.height = Math.ceil(1.4 * px);
    ctx.font = `${px}px sans-serif`;  // resizing the canvas reset it
    ctx.fillStyle = "#222222", ctx.textBaseline = "middle", ctx.textAlign = "center";
    ctx.fillText(text, canvas.width / 2, canvas.height / 2);
    const texture = new THREE.CanvasTexture(canvas);
    texture.colorSpace = THREE.SRGBColorSpace;
    const sprite = new THREE.Sprite(new THREE.SpriteMaterial({map: texture, depthTest: false}));
    // As large as fits between neighbours (step apart): the camera backs off
    // as the runs add up, and a tag of a fixed size would shrink to nothing.
    const h = Math.min(0.1 * step, (0.9 * step * canvas.height) / canvas.width);
    sprite.scale.set((h * canvas.width) / canvas.height, h, 1);
    sprite.position.copy(centre).setComponent(2, hi[2] + 0.15 * extent);
    sprite.renderOrder = 20;
    return sprite;
  };
  const jointRadius = 0.015 * extent;
  const jointMaterial = new THREE.MeshStandardMaterial({color: 0x333333, roughness: 0.5});
  const markerMaterial = new THREE.MeshStandardMaterial({color: MARKER_COLOUR, roughness: 0.4});
  if (!(G.markers || []).length) document.getElementById("markers-box").style.display = "none";

  const R = runs.map((run, k) => {
    const root = new THREE.Group();
    root.position.setComponent(side, k * step);
    scene.add(root);
    const bodies = G.bodies.map((b, i) => {
      const group = new THREE.Group();
      const colour = COLOURS[i % COLOURS.length];
      for (const v of b.visuals) {
        const material = new THREE.MeshStandardMaterial({color: colour, roughness: 0.6, metalness: 0.1,
                                                         transparent: v.shape === "ellipsoid", opacity: v.shape === "ellipsoid" ? 0.85 : 1});
        const mesh = new THREE.Mesh(shapeGeometry(v), material);
        mesh.position.set(v.position[0], v.position[1], v.position[2]);
        mesh.quaternion.copy(quat(v.quaternion));
        group.add(mesh);
      }
      root.add(group);
      // The trail of the centre of mass.
      const tg = new THREE.BufferGeometry();
      tg.setAttribute("position", new THREE.BufferAttribute(paths[k][i], 3));
      const trail = new THREE.Line(tg, new THREE.LineBasicMaterial({color: colour}));
      root.add(trail);
      return {group, trail};
    });
    const joints = G.joints.map((j) => {
      const m = new THREE.Mesh(new THREE.SphereGeometry(jointRadius, 12, 8), jointMaterial);
      m.position.set(j.point[0], j.point[1], j.point[2]);
      (j.body >= 0 ? bodies[j.body].group : root).add(m);
      return m;
    });
    // Arrows: the median of the run's reactions is 0.2 extent long (not the
    // largest: the peaks would shrink every other arrow to nothing).
    const magnitudes = [];
    for (const f of run.forces) for (let a = 0; a < f.length; a += 3) magnitudes.push(Math.hypot(f[a], f[a + 1], f[a + 2]));
    magnitudes.sort((a, b) => a - b);
    const fmax = magnitudes.length ? magnitudes[Math.floor(0.5 * (magnitudes.length - 1))] : 0;
    const arrows = run.force_joints.map(() => {
      const a = new THREE.ArrowHelper(new THREE.Vector3(1, 0, 0), new THREE.Vector3(), 1, 0xc00000);
      // Drawn over the bodies: a joint's point is often inside a shape.
      for (const part of [a.line, a.cone]) part.material.depthTest = false, part.renderOrder = 10;
      root.add(a);
      return a;
    });
    const label = document.createElement("label");
    const box = document.createElement("input");
    box.type = "checkbox", box.checked = true;
    label.append(box, ` ${run.name}`);  // text, not HTML: a folder name is shown as it is
    box.addEventListener("change", (e) => { root.visible = e.target.checked; draw(); });
    if (runs.length > 1) {
      document.getElementById("run-list").appendChild(label);
      root.add(nameTag(run.name));  // side by side, each copy says which run it is
    }
    // Markers: a gold dot on the body and the path of its point (the trail).
    const markers = (G.markers || []).map((mk) => {
      const dot = new THREE.Mesh(new THREE.SphereGeometry(0.6 * jointRadius, 12, 8), markerMaterial);
      dot.position.set(mk.point[0], mk.point[1], mk.point[2]);
      bodies[mk.body].group.add(dot);
      const c = new THREE.Vector3(...mk.point), pts = new Float32Array(3 * run.frames.length), i = mk.body;
      run.frames.forEach((fr, f) => {
        const p = c.clone().applyQuaternion(quat(fr.slice(7 * i + 3, 7 * i + 7)));
        pts[3 * f] = fr[7 * i] + p.x, pts[3 * f + 1] = fr[7 * i + 1] + p.y, pts[3 * f + 2] = fr[7 * i + 2] + p.z;
      });
      const tg = new THREE.BufferGeometry();
      tg.setAttribute("position", new THREE.BufferAttribute(pts, 3));
      const trail = new THREE.Line(tg, new THREE.LineBasicMaterial({color: MARKER_COLOUR}));
      root.add(trail);
      return {dot, trail};
    });
    return {run, root, bodies, joints, arrows, markers, forceScale: fmax > 0 ? (0.2 * extent) / fmax : 0};
  });

  const t0 = Math.min(...runs.map((r) => r.times[0])), t1 = Math.max(...runs.map((r) => r.times[r.times.length - 1]));
  let t = t0, playing = true, speed = 1, last = null;
  const frameAt = (times, t) => {  // the last frame at or before t
    let a = 0, b = times.length - 1;
    if (t >= times[b]) return b;
    while (a < b) {
      const m = (a + b + 1) >> 1;
      if (times[m] <= t) a = m; else b = m - 1;
    }
    return a;
  };
  const show = {trails: true, forces: true, joints: true, markers: true};

  function place() {
    const tmp = new THREE.Vector3();
    for (const r of R) {
      const i = frameAt(r.run.times, t), f = r.run.frames[i];
      r.bodies.forEach((b, k) => {
        b.group.position.set(f[7 * k], f[7 * k + 1], f[7 * k + 2]);
        b.group.quaternion.copy(quat(f.slice(7 * k + 3, 7 * k + 7)));
        b.trail.geometry.setDrawRange(0, i + 1);
        b.trail.visible = show.trails;
      });
      r.joints.forEach((m) => { m.visible = show.joints; });
      r.markers.forEach((m) => {
        m.dot.visible = show.markers;
        m.trail.visible = show.markers && show.trails;
        m.trail.geometry.setDrawRange(0, i + 1);
      });
      r.run.force_joints.forEach((j, a) => {
        const arrow = r.arrows[a], F = r.run.forces[i].slice(3 * a, 3 * a + 3);
        const len = Math.min(Math.hypot(F[0], F[1], F[2]) * r.forceScale, 0.5 * extent);  // peaks capped
        arrow.visible = show.forces && len > 1e-9 * extent;
        if (!arrow.visible) return;
        r.root.updateMatrixWorld(true);
        r.joints[j].getWorldPosition(tmp);
        r.root.worldToLocal(tmp);
        arrow.position.copy(tmp);
        arrow.setDirection(new THREE.Vector3(F[0], F[1], F[2]).normalize());
        arrow.setLength(len, Math.min(0.3 * len, 0.08 * extent), Math.min(0.15 * len, 0.04 * extent));
      });
    }
    document.getElementById("clock").textContent = `t = ${t.toFixed(3)} s`;
    document.getElementById("time").value = String(Math.round(((t - t0) / Math.max(t1 - t0, 1e-300)) * 10000));
  }

  // The camera looks along the axis the motion spans least, a little from
  // above and aside, far enough back to see every run.
  const view_dir = new THREE.Vector3();
  view_dir.setComponent(depth, -1);
  if (depth === 2) view_dir.set(0.3, -0.5, 1);
  else {
    view_dir.z = 0.35;
    view_dir.setComponent(side, 0.25);
  }
  view_dir.normalize();
  const target = centre.clone();
  target.setComponent(side, target.getComponent(side) + ((runs.length - 1) * step) / 2);
  const size = Math.max(span[0], span[1], span[2], ((runs.length - 1) * step + span[side]));
  let distance = (0.5 * size) / Math.tan((camera.fov * Math.PI) / 360) + 0.5 * span[depth];
  let azimuth = Math.atan2(view_dir.y, view_dir.x), elevation = Math.asin(view_dir.z);
  function aim() {
    camera.position.set(target.x + distance * Math.cos(elevation) * Math.cos(azimuth),
                        target.y + distance * Math.cos(elevation) * Math.sin(azimuth),
                        target.z + distance * Math.sin(elevation));
    camera.lookAt(target);
  }
  const axes = new THREE.AxesHelper(0.15 * extent);
  scene.add(axes);

  function resize() {
    const w = view.clientWidth || window.innerWidth, h = view.clientHeight || window.innerHeight;
    renderer.setSize(w, h);
    camera.aspect = w / Math.max(h, 1);
    camera.updateProjectionMatrix();
  }
  function draw() {
    place();
    aim();
    renderer.render(scene, camera);
  }

  // Mouse: drag turns the view about the scene's centre, the wheel zooms.
  let drag = null;
  renderer.domElement.addEventListener("pointerdown", (e) => { drag = [e.clientX, e.clientY]; });
  window.addEventListener("pointerup", () => { drag = null; });
  window.addEventListener("pointermove", (e) => {
    if (!drag) return;
    azimuth -= (e.clientX - drag[0]) * 0.01;
    elevation = Math.max(-1.5, Math.min(1.5, elevation + (e.clientY - drag[1]) * 0.01));
    drag = [e.clientX, e.clientY];
    draw();
  });
  renderer.domElement.addEventListener("wheel", (e) => {
    e.preventDefault();
    distance *= Math.exp(e.deltaY * 0.001);
    draw();
  }, {passive: false});

  const play = document.getElementById("play");
  const setPlaying = (p) => { playing = p; play.textContent = p ? "pause" : "play"; last = null; };
  play.addEventListener("click", () => setPlaying(!playing));
  document.getElementById("speed").addEventListener("change", (e) => { speed = parseFloat(e.target.value); });
  document.getElementById("time").addEventListener("input", (e) => {
    setPlaying(false);
    t = t0 + (parseFloat(e.target.value) / 10000) * (t1 - t0);
    draw();
  });
  for (const k of ["trails", "forces", "joints", "markers"])
    document.getElementById(`show-${k}`).addEventListener("change", (e) => { show[k] = e.target.checked; draw(); });

  const fromHash = () => {
    const m = /(?:^#|&)t=([-+0-9.eE]+)/.exec(window.location.hash);
    if (!m) return false;
    t = Math.min(t1, Math.max(t0, parseFloat(m[1])));
    setPlaying(false);
    return true;
  };
  window.addEventListener("hashchange", () => { if (fromHash()) draw(); });
  window.addEventListener("resize", () => { resize(); draw(); });
  fromHash();
  resize();
  draw();
  document.title += " [ready]";

  function tick(now) {
    if (playing) {
      if (last !== null) {
        t += ((now - last) / 1000) * speed;
        if (t > t1) t = t0;  // loop
      }
      last = now;
      draw();
    }
    requestAnimationFrame(tick);
  }
  requestAnimationFrame(tick);
}
