// The keyframes and the graph between them: each keyframe as a small frustum in its map's colour, each map's
// keyframe path (keyframes in the order they were made), covisibility edges (faint) and loop edges (bold).
// Messages only record what changed; the lines are rebuilt at most once per drawn frame.
import { Group } from 'three';
import { COVISIBILITY_EDGE_COLOUR, LOOP_EDGE_COLOUR, mapColour } from './map-colours.js';
import { cameraCentre, FrustumShape, FRUSTUM_SEGMENTS, PLACEHOLDER_CAMERA } from './pose.js';
import { boldLines, setSegments, thinLines } from './lines.js';

const KEYFRAME_FRUSTUM_DEPTH = 0.06; // metres: small enough for a room-sized map to stay readable
const LOOP_EDGE_WIDTH = 3; // pixels

export class KeyframeGraph {
  constructor() {
    this.frusta = thinLines({ vertexColors: true });
    this.paths = thinLines({ vertexColors: true, transparent: true, opacity: 0.8 });
    this.covisibilityEdges = thinLines({ color: COVISIBILITY_EDGE_COLOUR, transparent: true, opacity: 0.12 });
    this.loopEdges = boldLines({ color: LOOP_EDGE_COLOUR }, LOOP_EDGE_WIDTH);
    this.group = new Group();
    this.group.add(this.covisibilityEdges, this.paths, this.frusta, this.loopEdges);
    this.setCamera(PLACEHOLDER_CAMERA);
    this.clear();
  }

  /** The camera whose field of view the frusta show (hello's camera). */
  setCamera(camera) {
    this.frustumShape = new FrustumShape(camera, KEYFRAME_FRUSTUM_DEPTH);
    this.dirty = true;
  }

  clear() {
    this.keyframes = new Map(); // id → { map, T_wc }
    this.keyframesPerMap = new Map();
    this.covisibility = [];
    this.loops = [];
    this.dirty = true;
  }

  /** Keyframes of one map held, as of the last rebuild. */
  countOfMap(mapId) {
    return this.keyframesPerMap.get(mapId) ?? 0;
  }

  /** Takes a map message's keyframe changes; edge lists come whole, and only when they changed. */
  apply({ keyframes = [], removed_keyframes: removed = [], covisibility, loops }) {
    for (const { id, map, T_wc } of keyframes) this.keyframes.set(id, { map, T_wc });
    for (const id of removed) this.keyframes.delete(id);
    if (covisibility) this.covisibility = covisibility;
    if (loops) this.loops = loops;
    this.dirty = true;
  }

  /** Rebuilds the lines if anything changed since the last call; tells whether it did. */
  rebuild() {
    if (!this.dirty) return false;
    this.dirty = false;
    this.rebuildFrustaAndPaths();
    setSegments(this.covisibilityEdges, this.edgeSegments(this.covisibility));
    setSegments(this.loopEdges, this.edgeSegments(this.loops));
    return true;
  }

  rebuildFrustaAndPaths() {
    const frustumPositions = [];
    const frustumColours = [];
    const pathPositions = [];
    const pathColours = [];
    const previousCentreOfMap = new Map();
    this.keyframesPerMap = new Map();
    const ids = [...this.keyframes.keys()].sort((a, b) => a - b);
    for (const id of ids) {
      const { map, T_wc } = this.keyframes.get(id);
      const colour = mapColour(map).toArray();
      this.frustumShape.appendSegments(T_wc, frustumPositions);
      for (let end = 0; end < 2 * FRUSTUM_SEGMENTS; end += 1) frustumColours.push(...colour);
      const centre = cameraCentre(T_wc);
      const previous = previousCentreOfMap.get(map);
      if (previous) {
        pathPositions.push(...previous, ...centre);
        pathColours.push(...colour, ...colour);
      }
      previousCentreOfMap.set(map, centre);
      this.keyframesPerMap.set(map, (this.keyframesPerMap.get(map) ?? 0) + 1);
    }
    setSegments(this.frusta, frustumPositions, frustumColours);
    setSegments(this.paths, pathPositions, pathColours);
  }

  /** Segments between the centres of each pair of keyframes held (a pair naming one not held is skipped). */
  edgeSegments(pairs) {
    const positions = [];
    for (const [a, b] of pairs) {
      const first = this.keyframes.get(a);
      const second = this.keyframes.get(b);
      if (first && second) positions.push(...cameraCentre(first.T_wc), ...cameraCentre(second.T_wc));
    }
    return positions;
  }
}
