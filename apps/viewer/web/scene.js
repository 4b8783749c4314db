// The 3D view: trajectory, keyframe frustums (reactivated ones highlighted), map points coloured
// by intensity, loop-closure edges and the current camera, with orbit controls that follow the
// camera. World coordinates are the first camera's (x right, y down, z forward); the scene root
// turns them so that "up" is -y.
'use strict';

class LdsmScene {
  constructor(container) {
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(window.devicePixelRatio || 1);
    this.renderer.setClearColor(0x15171c);
    container.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(60, 1, 0.01, 5000);
    this.camera.position.set(0, 3, -6);
    this.controls = new THREE.OrbitControls(this.camera, this.renderer.domElement);
    this.controls.enableDamping = true;
    this.root = new THREE.Group();
    this.root.rotation.x = Math.PI;  // camera y (down) -> screen down
    this.scene.add(this.root);
    this.follow = true;
    this.frustumSize = 0.1;
    this.lastFollowed = null;

    this.trajectory = this.makeLine(new THREE.Line(new THREE.BufferGeometry(),
      new THREE.LineBasicMaterial({ color: 0x4fc3f7 })), 3);
    this.frustums = this.makeLine(new THREE.LineSegments(new THREE.BufferGeometry(),
      new THREE.LineBasicMaterial({ vertexColors: THREE.VertexColors })), 3, true);
    this.loops = this.makeLine(new THREE.LineSegments(new THREE.BufferGeometry(),
      new THREE.LineBasicMaterial({ color: 0xef5350 })), 3);
    this.current = this.makeLine(new THREE.LineSegments(new THREE.BufferGeometry(),
      new THREE.LineBasicMaterial({ color: 0x66bb6a })), 3);
    this.points = this.makeLine(new THREE.Points(new THREE.BufferGeometry(),
      new THREE.PointsMaterial({ size: 2, sizeAttenuation: false,
        vertexColors: THREE.VertexColors })), 3, true);
    this.pendingDraw = true;
    this.controls.addEventListener('change', () => { this.pendingDraw = true; });
    window.addEventListener('resize', () => { this.resize(); this.pendingDraw = true; });
    this.resize();
  }

  makeLine(object, itemSize, withColour) {
    object.frustumCulled = false;
    object.userData.capacity = 0;
    object.userData.itemSize = itemSize;
    object.userData.withColour = !!withColour;
    this.root.add(object);
    return object;
  }

  // Makes room for `n` vertices in an object's geometry (doubling), keeping nothing; true when
  // the geometry was replaced.
  reserve(object, n) {
    const u = object.userData;
    if (n <= u.capacity && u.capacity > 0) return false;
    let cap = Math.max(u.capacity, 256);
    while (cap < n) cap *= 2;
    const g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.BufferAttribute(new Float32Array(cap * 3), 3));
    if (u.withColour)
      g.setAttribute('color', new THREE.BufferAttribute(new Float32Array(cap * 3), 3));
    object.geometry.dispose();
    object.geometry = g;
    u.capacity = cap;
    return true;
  }

  resize() {
    const w = window.innerWidth, h = window.innerHeight;
    this.renderer.setSize(w, h);
    this.camera.aspect = w / Math.max(h, 1);
    this.camera.updateProjectionMatrix();
  }

  // trajectory: Stream of poses (x y z qx qy qz qw)
  updateTrajectory(stream) {
    const n = stream.length;
    this.reserve(this.trajectory, n);
    const pos = this.trajectory.geometry.attributes.position.array;
    for (let i = 0; i < n; ++i) {
      pos[3 * i] = stream.data[7 * i];
      pos[3 * i + 1] = stream.data[7 * i + 1];
      pos[3 * i + 2] = stream.data[7 * i + 2];
    }
    this.trajectory.geometry.attributes.position.needsUpdate = true;
    this.trajectory.geometry.setDrawRange(0, n);
    this.updateScale(stream);
  }

  // The frustum size follows the size of the scene (monocular maps have no metric scale).
  updateScale(stream) {
    const n = stream.length;
    if (n < 2) return;
    let min = [Infinity, Infinity, Infinity], max = [-Infinity, -Infinity, -Infinity];
    for (let i = 0; i < n; ++i)
      for (let k = 0; k < 3; ++k) {
        const v = stream.data[7 * i + k];
        if (v < min[k]) min[k] = v;
        if (v > max[k]) max[k] = v;
      }
    const extent = Math.hypot(max[0] - min[0], max[1] - min[1], max[2] - min[2]);
    this.frustumSize = Math.max(0.05 * extent, 1e-3);
  }

  // The 16 vertices (8 segments) of a camera frustum at pose p (7 floats at offset o).
  frustumVertices(d, o, size, out, at) {
    const q = new THREE.Quaternion(d[o + 3], d[o + 4], d[o + 5], d[o + 6]);
    const c = new THREE.Vector3(d[o], d[o + 1], d[o + 2]);
    const w = size, h = size * 0.75, z = size;
    const corners = [[-w, -h, z], [w, -h, z], [w, h, z], [-w, h, z]].map(
      (v) => new THREE.Vector3(v[0], v[1], v[2]).applyQuaternion(q).add(c));
    const segs = [];
    for (let i = 0; i < 4; ++i) segs.push(c, corners[i], corners[i], corners[(i + 1) % 4]);
    for (let i = 0; i < 16; ++i) {
      out[3 * (at + i)] = segs[i].x;
      out[3 * (at + i) + 1] = segs[i].y;
      out[3 * (at + i) + 2] = segs[i].z;
    }
  }

  updateKeyframes(stream, reactivated) {
    const n = stream.length;
    this.reserve(this.frustums, n * 16);
    const g = this.frustums.geometry;
    const pos = g.attributes.position.array, col = g.attributes.color.array;
    const re = new Set(reactivated || []);
    for (let i = 0; i < n; ++i) {
      this.frustumVertices(stream.data, 7 * i, this.frustumSize * 0.5, pos, 16 * i);
      const rgb = re.has(i) ? [1.0, 0.70, 0.0] : [0.36, 0.42, 0.75];
      for (let k = 0; k < 16; ++k) col.set(rgb, 3 * (16 * i + k));
    }
    g.attributes.position.needsUpdate = true;
    g.attributes.color.needsUpdate = true;
    g.setDrawRange(0, n * 16);
  }

  updateLoops(keyframes, edges) {
    const n = edges ? edges.length : 0;
    this.reserve(this.loops, n * 2);
    const pos = this.loops.geometry.attributes.position.array;
    let m = 0;
    for (let i = 0; i < n; ++i) {
      const [a, b] = edges[i];
      if (a >= keyframes.length || b >= keyframes.length) continue;
      for (const k of [a, b]) {
        pos.set(keyframes.data.subarray(7 * k, 7 * k + 3), 3 * m);
        ++m;
      }
    }
    this.loops.geometry.attributes.position.needsUpdate = true;
    this.loops.geometry.setDrawRange(0, m);
  }

  updateCurrent(pose) {
    if (!pose) return;
    this.reserve(this.current, 16);
    const pos = this.current.geometry.attributes.position.array;
    this.frustumVertices(pose, 0, this.frustumSize, pos, 0);
    this.current.geometry.attributes.position.needsUpdate = true;
    this.current.geometry.setDrawRange(0, 16);
    if (this.follow) this.followCamera(pose);
  }

  // Moves the orbit target (and the eye with it) to the camera, keeping the user's view angle.
  followCamera(pose) {
    const p = new THREE.Vector3(pose[0], pose[1], pose[2]);
    this.root.localToWorld(p);
    if (this.lastFollowed === null) {
      this.controls.target.copy(p);
      const back = Math.max(this.frustumSize * 40, 1.0);
      // Behind and above the camera (its forward axis is -z in the scene).
      this.camera.position.set(p.x - back * 0.2, p.y + back * 0.8, p.z + back);
    } else {
      const delta = p.clone().sub(this.lastFollowed);
      this.controls.target.add(delta);
      this.camera.position.add(delta);
    }
    this.lastFollowed = p;
  }

  // Shows the whole trajectory from above and behind its start.
  fitAll(stream) {
    const n = stream.length;
    if (n === 0) return;
    const box = new THREE.Box3();
    for (let i = 0; i < n; ++i)
      box.expandByPoint(new THREE.Vector3(stream.data[7 * i], stream.data[7 * i + 1],
        stream.data[7 * i + 2]));
    box.applyMatrix4(this.root.matrixWorld);
    const centre = box.getCenter(new THREE.Vector3());
    const r = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 1e-3);
    this.controls.target.copy(centre);
    this.camera.position.set(centre.x + 0.2 * r, centre.y + 1.1 * r, centre.z + 1.0 * r);
    this.lastFollowed = null;
  }

  updatePoints(stream) {
    const n = stream.length;
    if (this.reserve(this.points, n)) stream.changedFrom = 0;
    const g = this.points.geometry;
    const pos = g.attributes.position.array, col = g.attributes.color.array;
    for (let i = stream.changedFrom; i < n; ++i) {
      const d = stream.data;
      pos[3 * i] = d[4 * i];
      pos[3 * i + 1] = d[4 * i + 1];
      pos[3 * i + 2] = d[4 * i + 2];
      const v = d[4 * i + 3];
      if (v < 0) {  // corner point
        col[3 * i] = 1.0; col[3 * i + 1] = 0.35; col[3 * i + 2] = 0.1;
      } else {
        const gv = 0.25 + 0.75 * Math.min(v, 255) / 255;
        col[3 * i] = col[3 * i + 1] = col[3 * i + 2] = gv;
      }
    }
    stream.changedFrom = n;
    g.attributes.position.needsUpdate = true;
    g.attributes.color.needsUpdate = true;
    g.setDrawRange(0, n);
  }

  // Draws when the data or the view changed (a page left open on the robot itself costs
  // nothing between updates); `changed`: new data this frame.
  render(changed) {
    const moved = this.controls.update();
    if (!changed && !moved && !this.pendingDraw) return false;
    this.renderer.render(this.scene, this.camera);
    this.pendingDraw = false;
    return true;
  }
}
