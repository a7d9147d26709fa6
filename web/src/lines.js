// Line objects whose segments are replaced as a whole when what they show changes (keyframes, edges, the current
// camera). Thin lines are plain WebGL lines; bold ones (loop edges, the current camera) need LineSegments2, since
// WebGL draws every plain line one pixel wide.
import { BufferAttribute, BufferGeometry, LineBasicMaterial, LineSegments } from 'three';
import { LineMaterial } from 'three/examples/jsm/lines/LineMaterial.js';
import { LineSegments2 } from 'three/examples/jsm/lines/LineSegments2.js';
import { LineSegmentsGeometry } from 'three/examples/jsm/lines/LineSegmentsGeometry.js';

/** Thin segments; with `vertexColors` each segment end takes its colour from the colours given to `setSegments`. */
export function thinLines(materialOptions) {
  return prepared(new LineSegments(new BufferGeometry(), new LineBasicMaterial(materialOptions)));
}

/** Segments `width` pixels wide whatever the distance (LineSegments2 reads the viewport's size as it draws). */
export function boldLines(materialOptions, width) {
  const material = new LineMaterial({ ...materialOptions, linewidth: width });
  return prepared(new LineSegments2(new LineSegmentsGeometry(), material));
}

/**
 * Replaces the segments drawn: `positions` holds x, y, z of both ends of each segment, `colours` (optional) r, g, b
 * of each end. Nothing to draw hides the object (an empty geometry has no bounds to compute).
 */
export function setSegments(lines, positions, colours = null) {
  lines.visible = positions.length > 0;
  if (!lines.visible) return;
  let geometry;
  if (lines.isLineSegments2) {
    geometry = new LineSegmentsGeometry();
    geometry.setPositions(positions);
    if (colours) geometry.setColors(colours);
  } else {
    geometry = new BufferGeometry();
    geometry.setAttribute('position', new BufferAttribute(new Float32Array(positions), 3));
    if (colours) geometry.setAttribute('color', new BufferAttribute(new Float32Array(colours), 3));
  }
  lines.geometry.dispose();
  lines.geometry = geometry;
}

function prepared(lines) {
  // Their bounds change with every replacement and are not worth recomputing for culling.
  lines.frustumCulled = false;
  lines.visible = false;
  return lines;
}
