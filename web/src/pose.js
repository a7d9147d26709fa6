// Camera poses as the protocol sends them: T_wc, camera-to-world, a row-major 4×4 as 16 numbers, metres. The
// camera looks along its +z with x right and y down, like the image.

/** The world position of a point given in the camera's frame. */
function toWorld(T_wc, x, y, z) {
  return [
    T_wc[0] * x + T_wc[1] * y + T_wc[2] * z + T_wc[3],
    T_wc[4] * x + T_wc[5] * y + T_wc[6] * z + T_wc[7],
    T_wc[8] * x + T_wc[9] * y + T_wc[10] * z + T_wc[11],
  ];
}

/** The camera's centre in the world. */
export function cameraCentre(T_wc) {
  return [T_wc[3], T_wc[7], T_wc[11]];
}

/**
 * A camera drawn as a frustum: the image's rectangle at a fixed depth in front of the centre, joined to the
 * centre, so its opening is the camera's field of view (from hello's camera).
 */
export class FrustumShape {
  constructor(camera, depth) {
    const { fx, fy, cx, cy, width, height } = camera;
    const corner = (u, v) => [((u - cx) / fx) * depth, ((v - cy) / fy) * depth, depth];
    this.corners = [corner(0, 0), corner(width, 0), corner(width, height), corner(0, height)];
  }

  /** Appends the frustum's 8 line segments at pose T_wc to `positions` (x, y, z of both ends, one after the other). */
  appendSegments(T_wc, positions) {
    const centre = cameraCentre(T_wc);
    const corners = this.corners.map(([x, y, z]) => toWorld(T_wc, x, y, z));
    for (let i = 0; i < 4; i += 1) {
      positions.push(...centre, ...corners[i]);
      positions.push(...corners[i], ...corners[(i + 1) % 4]);
    }
  }
}

/** Line segments a frustum has: colour arrays are sized from it. */
export const FRUSTUM_SEGMENTS = 8;

/** The camera assumed until hello tells the run's own. */
export const PLACEHOLDER_CAMERA = { fx: 525, fy: 525, cx: 319.5, cy: 239.5, width: 640, height: 480 };
