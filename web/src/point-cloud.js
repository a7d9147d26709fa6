// The map's points in one growable buffer. Points come and go by id (added, moved by bundle adjustment or a loop
// closure, removed as outliers); each id holds one slot of the buffer, and a removed point's slot is filled with
// the last point so the drawn range stays packed.
import { BufferAttribute, BufferGeometry, Points, PointsMaterial } from 'three';
import { mapColour } from './map-colours.js';

const INITIAL_CAPACITY = 4096;
// How much of a point's colour is its map's colour, for maps other than the main one.
const OTHER_MAP_TINT = 0.55;

export class PointCloud {
  constructor() {
    this.material = new PointsMaterial({ size: 2.5, sizeAttenuation: false, vertexColors: true });
    this.points = new Points(new BufferGeometry(), this.material);
    // The buffer changes without its bounding sphere being recomputed: never cull it.
    this.points.frustumCulled = false;
    this.mainMap = 0;
    this.clear();
  }

  /** Forgets every point (a full map message follows). */
  clear() {
    this.count = 0;
    this.slotOfId = new Map();
    this.pointsPerMap = new Map();
    this.allocate(INITIAL_CAPACITY);
  }

  /** Points held of one map. */
  countOfMap(mapId) {
    return this.pointsPerMap.get(mapId) ?? 0;
  }

  /** Adds or moves points, given as the protocol's `points` object (ids, map, xyz, rgb). */
  upsert({ ids, map, xyz, rgb }) {
    for (let i = 0; i < ids.length; i += 1) {
      let slot = this.slotOfId.get(ids[i]);
      if (slot === undefined) {
        if (this.count === this.capacity) this.allocate(this.capacity * 2);
        slot = this.count;
        this.count += 1;
        this.slotOfId.set(ids[i], slot);
        this.ids[slot] = ids[i];
      } else {
        this.countMap(this.mapOfSlot[slot], -1);
      }
      this.mapOfSlot[slot] = map[i];
      this.countMap(map[i], +1);
      for (let c = 0; c < 3; c += 1) {
        this.positions[3 * slot + c] = xyz[3 * i + c];
        this.rgb[3 * slot + c] = rgb[3 * i + c];
      }
      this.colourSlot(slot);
    }
    this.changed();
  }

  remove(ids) {
    for (const id of ids) {
      const slot = this.slotOfId.get(id);
      if (slot === undefined) continue;
      this.slotOfId.delete(id);
      this.countMap(this.mapOfSlot[slot], -1);
      this.count -= 1;
      const last = this.count;
      if (slot !== last) this.moveSlot(last, slot);
    }
    this.changed();
  }

  /** Points of the main map keep their own colour; the others are tinted by their map's colour. */
  setMainMap(mapId) {
    if (mapId === this.mainMap) return;
    this.mainMap = mapId;
    for (let slot = 0; slot < this.count; slot += 1) this.colourSlot(slot);
    this.changed();
  }

  /** The positions held, as x, y, z one after the other (a view of the buffer: read it, do not keep it). */
  heldPositions() {
    return this.positions.subarray(0, 3 * this.count);
  }

  countMap(mapId, change) {
    const count = (this.pointsPerMap.get(mapId) ?? 0) + change;
    if (count === 0) this.pointsPerMap.delete(mapId);
    else this.pointsPerMap.set(mapId, count);
  }

  colourSlot(slot) {
    const mapId = this.mapOfSlot[slot];
    const tint = mapId === this.mainMap ? 0 : OTHER_MAP_TINT;
    const colour = mapColour(mapId);
    const channels = [colour.r, colour.g, colour.b];
    for (let c = 0; c < 3; c += 1) {
      this.colours[3 * slot + c] = Math.round((1 - tint) * this.rgb[3 * slot + c] + tint * 255 * channels[c]);
    }
  }

  moveSlot(from, to) {
    this.positions.copyWithin(3 * to, 3 * from, 3 * from + 3);
    this.rgb.copyWithin(3 * to, 3 * from, 3 * from + 3);
    this.colours.copyWithin(3 * to, 3 * from, 3 * from + 3);
    this.mapOfSlot[to] = this.mapOfSlot[from];
    this.ids[to] = this.ids[from];
    this.slotOfId.set(this.ids[to], to);
  }

  /** (Re)allocates the buffers with room for `capacity` points, keeping the points held. */
  allocate(capacity) {
    const resized = (Type, old, stride) => {
      const array = new Type(stride * capacity);
      if (old) array.set(old.subarray(0, stride * this.count));
      return array;
    };
    this.positions = resized(Float32Array, this.positions, 3);
    this.rgb = resized(Uint8Array, this.rgb, 3);
    this.colours = resized(Uint8Array, this.colours, 3);
    this.mapOfSlot = resized(Int32Array, this.mapOfSlot, 1);
    this.ids = resized(Float64Array, this.ids, 1);
    this.capacity = capacity;
    // A buffer of another size needs a new geometry: WebGL buffers keep the size they were made with.
    const geometry = new BufferGeometry();
    geometry.setAttribute('position', new BufferAttribute(this.positions, 3));
    geometry.setAttribute('color', new BufferAttribute(this.colours, 3, true));
    this.points.geometry.dispose();
    this.points.geometry = geometry;
    this.changed();
  }

  changed() {
    const geometry = this.points.geometry;
    geometry.setDrawRange(0, this.count);
    geometry.attributes.position.needsUpdate = true;
    geometry.attributes.color.needsUpdate = true;
  }
}
