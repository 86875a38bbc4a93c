// One WebGL view of a triangle mesh (three.js): orbit / zoom with the mouse, wireframe toggle, colours per vertex
// or per face. Renders on demand (after a change), not in a loop: the page stays idle when nothing moves.
import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';

export class MeshViewer {
  constructor(container) {
    this.container = container;
    // preserveDrawingBuffer: the canvas can be read back (screenshots, the browser tests' pixel checks).
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(Math.min(2, window.devicePixelRatio || 1));
    this.renderer.setClearColor(0xffffff, 1);
    // Debian 12's three.js is r111, whose defaults predate the physical light units (the default since r155) and
    // the encoded output (r152): asked for here, so the light intensities below mean what they mean in current
    // three.js and the vertex colours (linear values) reach the screen gamma-encoded (2.2, close to sRGB).
    this.renderer.physicallyCorrectLights = true;
    this.renderer.gammaOutput = true;
    this.renderer.gammaFactor = 2.2;
    container.appendChild(this.renderer.domElement);
    this.scene = new THREE.Scene();
    this.camera = new THREE.PerspectiveCamera(35, 1, 0.01, 1000);
    this.scene.add(new THREE.HemisphereLight(0xffffff, 0x667085, 1.6));
    this.light = new THREE.DirectionalLight(0xffffff, 1.6);
    this.camera.add(this.light);
    this.light.position.set(1, 1, 2);
    this.scene.add(this.camera);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.addEventListener('change', () => this.render());
    this.material = new THREE.MeshStandardMaterial({ vertexColors: true, roughness: 0.75, metalness: 0.0,
                                                     side: THREE.DoubleSide, flatShading: true });
    this.mesh = null;
    new ResizeObserver(() => this.resize()).observe(container);
    this.resize();
  }

  resize() {
    const w = this.container.clientWidth || 400, h = this.container.clientHeight || 300;
    this.renderer.setSize(w, h, true);
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
    this.render();
  }

  // positions: flat 3V; faces: flat 3F; colours: {perVertex: Float32Array 3V} or {perFace: Float32Array 3F} or null.
  // The geometry is unindexed (three vertices per face) so that per-face colours are exact.
  setMesh(positions, faces, colours, { keepCamera = false } = {}) {
    const nf = faces.length / 3;
    const pos = new Float32Array(9 * nf), col = new Float32Array(9 * nf);
    for (let f = 0; f < nf; ++f) {
      for (let k = 0; k < 3; ++k) {
        const v = faces[3 * f + k];
        for (let c = 0; c < 3; ++c) {
          pos[9 * f + 3 * k + c] = positions[3 * v + c];
          col[9 * f + 3 * k + c] = colours?.perFace ? colours.perFace[3 * f + c]
                                 : colours?.perVertex ? colours.perVertex[3 * v + c] : [0.62, 0.70, 0.82][c];
        }
      }
    }
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(pos, 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(col, 3));
    geometry.computeVertexNormals();
    geometry.computeBoundingSphere();
    if (this.mesh) { this.scene.remove(this.mesh); this.mesh.geometry.dispose(); }
    this.mesh = new THREE.Mesh(geometry, this.material);
    this.scene.add(this.mesh);
    if (!keepCamera) this.frame(geometry.boundingSphere);
    this.render();
  }

  frame(sphere) {
    const r = sphere.radius || 1;
    const dist = r / Math.sin((this.camera.fov * Math.PI) / 360) * 1.1;
    this.controls.target.copy(sphere.center);
    this.camera.position.copy(sphere.center).add(new THREE.Vector3(0.3, 0.4, 1).normalize().multiplyScalar(dist));
    this.camera.near = dist / 100; this.camera.far = dist * 100;
    this.camera.updateProjectionMatrix();
    this.controls.update();
  }

  setWireframe(on) { this.material.wireframe = on; this.render(); }

  render() { this.renderer.render(this.scene, this.camera); }
}
