// SPDX-License-Identifier: MIT
// The 3D view (three.js): the shaded mesh, the path (best so far or final), s/t markers, an
// optional per-vertex field overlay, orbit controls, and vertex picking: a click (not a drag)
// casts a ray; the nearest corner of the hit triangle is the picked vertex.
//
// The default camera looks at the mesh's bounding-box centre from +z (y up), with a vertical
// field of view of 45 degrees, at a distance where the box fits; `cameraState()` reports it so
// tests can project known vertices themselves.

import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { Line2 } from 'three/addons/lines/Line2.js';
import { LineGeometry } from 'three/addons/lines/LineGeometry.js';
import { LineMaterial } from 'three/addons/lines/LineMaterial.js';

export const FOV_DEGREES = 45;
/// The field overlay's colour (unlit: its pixels are exactly this where a segment is drawn).
export const FIELD_COLOUR = 0x0d5966;

export class MeshView {
  constructor(container, { height = 480 } = {}) {
    this.container = container;
    const width = Math.max(320, container.clientWidth || 640);
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(1);
    this.renderer.setSize(width, height);
    this.renderer.setClearColor(0xf4f5f7);
    container.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(FOV_DEGREES, width / height, 0.01, 1000);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x445566, 1.2));
    this.light = new THREE.DirectionalLight(0xffffff, 1.6);
    this.scene.add(this.light);
    this.scene.add(this.light.target);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.addEventListener('change', () => this.requestRender());
    this.mesh = null;
    this.pathLine = null;
    this.markers = {};
    this.onPick = null;
    this.firstFrameAt = null;
    this.onFirstFrame = null;
    this.renderPending = false;
    this.installPicking();
  }

  /// Shows the mesh; `vertices` and `faces` are flat arrays (x y z ..., a b c ...).
  setGeometry(vertices, faces) {
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.Float32BufferAttribute(vertices, 3));
    geometry.setIndex(faces.length > 65535 * 3 || vertices.length / 3 > 65535
      ? new THREE.Uint32BufferAttribute(faces, 1) : new THREE.Uint16BufferAttribute(faces, 1));
    geometry.computeVertexNormals();
    geometry.computeBoundingBox();
    geometry.computeBoundingSphere();
    const material = new THREE.MeshStandardMaterial({
      color: 0xc8ccd6, roughness: 0.75, metalness: 0.0, side: THREE.DoubleSide, flatShading: false,
      // The surface is pushed back in depth so the path lying on it is never hidden by it.
      polygonOffset: true, polygonOffsetFactor: 1, polygonOffsetUnits: 1,
    });
    if (this.mesh) this.scene.remove(this.mesh);
    this.mesh = new THREE.Mesh(geometry, material);
    this.scene.add(this.mesh);
    this.vertices = vertices;
    const box = geometry.boundingBox;
    this.center = box.getCenter(new THREE.Vector3());
    this.size = box.getSize(new THREE.Vector3());
    this.diagonal = this.size.length() || 1;
    this.resetCamera();
  }

  /// Camera on +z looking at the box centre, far enough for the box's x/y extent to fit.
  resetCamera() {
    const tanHalf = Math.tan((FOV_DEGREES * Math.PI) / 360);
    const halfH = this.size.y / 2, halfW = this.size.x / 2;
    const fit = Math.max(halfH / tanHalf, halfW / (tanHalf * this.camera.aspect));
    const distance = 1.1 * fit + this.size.z / 2 || this.diagonal;
    this.camera.position.set(this.center.x, this.center.y, this.center.z + distance);
    this.camera.up.set(0, 1, 0);
    this.camera.near = distance / 100;
    this.camera.far = distance * 10 + this.diagonal * 4;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(this.center);
    this.controls.update();
    this.light.position.copy(this.camera.position).add(new THREE.Vector3(-0.3, 0.5, 0).multiplyScalar(distance));
    this.light.target.position.copy(this.center);
    this.requestRender();
  }

  /// Turns the camera (same target and distance) to look at the surface around the given
  /// vertices from outside: along their mean normal, or from the centre through them.
  lookAtVertices(ids) {
    const normals = this.mesh.geometry.getAttribute('normal');
    const dir = new THREE.Vector3();
    const mid = new THREE.Vector3();
    let n = 0;
    for (const id of ids) {
      if (id === null || id === undefined || id < 0 || id >= normals.count) continue;
      dir.add(new THREE.Vector3().fromBufferAttribute(normals, id));
      mid.add(this.vertex(id));
      ++n;
    }
    if (!n) return;
    mid.divideScalar(n);
    if (dir.length() < 0.3 * n) dir.copy(mid).sub(this.center);
    if (dir.lengthSq() === 0) return;
    dir.normalize();
    const distance = this.camera.position.distanceTo(this.controls.target);
    this.camera.position.copy(this.center).addScaledVector(dir, distance);
    this.camera.up.set(0, Math.abs(dir.y) > 0.9 ? 0 : 1, Math.abs(dir.y) > 0.9 ? 1 : 0);
    this.camera.lookAt(this.center);
    this.controls.update();
    const side = new THREE.Vector3().crossVectors(dir, this.camera.up).normalize();
    this.light.position.copy(this.camera.position).addScaledVector(this.camera.up, 0.5 * distance).addScaledVector(side, 0.3 * distance);
    this.requestRender();
  }

  cameraState() {
    return {
      position: this.camera.position.toArray(),
      target: this.controls.target.toArray(),
      up: this.camera.up.toArray(),
      fov: FOV_DEGREES,
      width: this.renderer.domElement.width,
      height: this.renderer.domElement.height,
    };
  }

  vertex(i) {
    return new THREE.Vector3(this.vertices[3 * i], this.vertices[3 * i + 1], this.vertices[3 * i + 2]);
  }

  /// The path as a thick line; `points` are [x, y, z] from source to target.
  setPath(points, { final = false } = {}) {
    if (this.pathLine) {
      this.scene.remove(this.pathLine);
      this.pathLine.geometry.dispose();
    }
    this.pathLine = null;
    if (!points || points.length < 2) return this.requestRender();
    const geometry = new LineGeometry();
    geometry.setPositions(points.flat());
    const material = new LineMaterial({ color: final ? 0xdb1414 : 0xf08a24, linewidth: final ? 4 : 3 });
    material.resolution.set(this.renderer.domElement.width, this.renderer.domElement.height);
    this.pathLine = new Line2(geometry, material);
    this.pathLine.renderOrder = 1;
    this.scene.add(this.pathLine);
    this.container.dataset.pathPoints = String(points.length);
    this.container.dataset.pathFinal = String(final);
    this.requestRender();
  }

  /// A sphere at vertex `id` ('s' green, 't' blue); null removes it.
  setMarker(name, id) {
    if (this.markers[name]) this.scene.remove(this.markers[name]);
    delete this.markers[name];
    if (id === null || id === undefined || !this.vertices || id < 0 || id >= this.vertices.length / 3) {
      return this.requestRender();
    }
    const sphere = new THREE.Mesh(
      new THREE.SphereGeometry(this.diagonal * 0.012, 20, 14),
      new THREE.MeshStandardMaterial({ color: name === 's' ? 0x0fa626 : 0x1a40f2, roughness: 0.4 }),
    );
    sphere.position.copy(this.vertex(id));
    this.markers[name] = sphere;
    this.scene.add(sphere);
    this.requestRender();
  }

  /// Short segments along a per-vertex field (flat x y z array) on at most ~3000 vertices;
  /// null removes them. The container's data-field-segments tells how many are drawn.
  setField(field) {
    if (this.fieldLines) {
      this.scene.remove(this.fieldLines);
      this.fieldLines.geometry.dispose();
      this.fieldLines.material.dispose();
    }
    this.fieldLines = null;
    this.container.dataset.fieldSegments = '0';
    if (!field || !this.vertices) return this.requestRender();
    const n = this.vertices.length / 3;
    const step = Math.max(1, Math.floor(n / 3000));
    const half = this.diagonal * 0.008;
    const positions = [];
    for (let i = 0; i < n; i += step) {
      const d = new THREE.Vector3(field[3 * i], field[3 * i + 1], field[3 * i + 2]);
      if (d.lengthSq() === 0) continue;
      d.normalize().multiplyScalar(half);
      const p = this.vertex(i);
      positions.push(p.x - d.x, p.y - d.y, p.z - d.z, p.x + d.x, p.y + d.y, p.z + d.z);
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.Float32BufferAttribute(positions, 3));
    this.fieldLines = new THREE.LineSegments(geometry, new THREE.LineBasicMaterial({ color: FIELD_COLOUR }));
    this.fieldLines.renderOrder = 2;
    this.scene.add(this.fieldLines);
    this.container.dataset.fieldSegments = String(positions.length / 6);
    this.requestRender();
  }

  /// The vertex under canvas pixel (x, y), or null when the ray misses the mesh.
  pick(x, y) {
    if (!this.mesh) return null;
    const canvas = this.renderer.domElement;
    const ndc = new THREE.Vector2((x / canvas.clientWidth) * 2 - 1, -(y / canvas.clientHeight) * 2 + 1);
    const raycaster = new THREE.Raycaster();
    raycaster.setFromCamera(ndc, this.camera);
    const hit = raycaster.intersectObject(this.mesh, false)[0];
    if (!hit || !hit.face) return null;
    let best = null;
    let bestDistance = Infinity;
    for (const v of [hit.face.a, hit.face.b, hit.face.c]) {
      const d = this.vertex(v).distanceToSquared(hit.point);
      if (d < bestDistance) {
        bestDistance = d;
        best = v;
      }
    }
    return best;
  }

  installPicking() {
    const canvas = this.renderer.domElement;
    let down = null;
    canvas.addEventListener('pointerdown', (e) => {
      down = { x: e.clientX, y: e.clientY };
    });
    canvas.addEventListener('pointerup', (e) => {
      if (!down || !this.onPick) return;
      const moved = Math.hypot(e.clientX - down.x, e.clientY - down.y);
      down = null;
      if (moved > 4) return;  // a drag rotates the view, it does not pick
      const rect = canvas.getBoundingClientRect();
      const v = this.pick(e.clientX - rect.left, e.clientY - rect.top);
      if (v !== null) this.onPick(v);
    });
  }

  requestRender() {
    if (this.renderPending) return;
    this.renderPending = true;
    requestAnimationFrame(() => {
      this.renderPending = false;
      this.renderer.render(this.scene, this.camera);
      if (this.firstFrameAt === null && this.mesh) {
        this.firstFrameAt = performance.now();
        this.container.dataset.firstFrameMs = this.firstFrameAt.toFixed(1);
        if (this.onFirstFrame) this.onFirstFrame(this.firstFrameAt);
      }
    });
  }
}
