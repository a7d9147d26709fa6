// The dense map: one triangle mesh with its vertices' colours, replaced whole by each `dense` message (a run shows
// its final map once it is built, or a coarse one now and then while it grows). Its arrays come as base64 of
// little-endian bytes (docs/viewer.md): float32 positions, uint8 colours, uint32 indices.
import { BufferAttribute, BufferGeometry, DoubleSide, Mesh, MeshBasicMaterial } from 'three';

// A mesh without colours is drawn in one grey.
const UNCOLOURED = 0x9aa5b1;

/** The bytes a base64 string holds. */
function decodeBase64(text) {
  const binary = atob(text);
  const bytes = new Uint8Array(binary.length);
  for (let i = 0; i < binary.length; i += 1) bytes[i] = binary.charCodeAt(i);
  return bytes;
}

export class DenseMesh {
  constructor() {
    // Unlit: the colours are what the camera saw, shading and all. Both sides, since a TSDF mesh is seen from behind
    // wherever the cameras never stood.
    this.mesh = new Mesh(new BufferGeometry(), new MeshBasicMaterial({ side: DoubleSide }));
    this.mesh.visible = false;
    this.triangles = 0;
  }

  /** Whether a mesh is held. */
  get held() {
    return this.triangles > 0;
  }

  /** Takes a `dense` message; throws on arrays that do not fit its counts. */
  set({ vertices, triangles, positions, rgb, indices }) {
    const xyz = new Float32Array(decodeBase64(positions).buffer);
    const corners = new Uint32Array(decodeBase64(indices).buffer);
    const colours = decodeBase64(rgb);
    if (xyz.length !== 3 * vertices || corners.length !== 3 * triangles ||
        (colours.length !== 0 && colours.length !== 3 * vertices)) {
      throw new Error(`dense map: ${xyz.length / 3} positions, ${colours.length / 3} colours and `
        + `${corners.length / 3} triangles for ${vertices} vertices and ${triangles} triangles`);
    }
    const geometry = new BufferGeometry();
    geometry.setAttribute('position', new BufferAttribute(xyz, 3));
    if (colours.length > 0) geometry.setAttribute('color', new BufferAttribute(colours, 3, true));
    geometry.setIndex(new BufferAttribute(corners, 1));
    this.mesh.geometry.dispose();
    this.mesh.geometry = geometry;
    this.mesh.material.vertexColors = colours.length > 0;
    this.mesh.material.color.set(colours.length > 0 ? 0xffffff : UNCOLOURED);
    this.mesh.material.needsUpdate = true;
    this.triangles = triangles;
  }

  /** Triangles drawn: none while hidden. */
  drawnTriangles() {
    return this.mesh.visible ? this.triangles : 0;
  }
}
