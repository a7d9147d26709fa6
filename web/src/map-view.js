// The 3D map: points, keyframes and their graph, the dense map when the run makes one, the current camera, and a view
// a person can orbit or let follow the camera. The world frame is the camera's (x right, y down, z forward), so the view's "up" is −y.
import { LinearSRGBColorSpace, PerspectiveCamera, Scene, Vector3, WebGLRenderer } from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { DenseMesh } from './dense-mesh.js';
import { element, formatCount, legendItem, setText } from './dom.js';
import { KeyframeGraph } from './keyframe-graph.js';
import { boldLines, setSegments } from './lines.js';
import {
  BACKGROUND_COLOUR, cssColour, CURRENT_CAMERA_COLOUR, LOOP_EDGE_COLOUR, LOST_CAMERA_COLOUR, mapColour,
} from './map-colours.js';
import { PointCloud } from './point-cloud.js';
import { cameraCentre, FrustumShape, PLACEHOLDER_CAMERA } from './pose.js';

const CURRENT_CAMERA_DEPTH = 0.12; // metres: twice a keyframe's, so the camera stands out among them
const CURRENT_CAMERA_WIDTH = 3; // pixels
// Where the view starts, from the point it looks at: above (−y) and behind (−z) a camera at that point.
const VIEW_OFFSET = new Vector3(0, -1.2, -2.2);
// What the run changes (the camera, the map) is drawn at most this often: rendering the scene is the page's
// dearest work, done on the CPU where there is no GPU, and the frame panel beside it should keep the run's pace.
// A person turning the view is answered at once.
const RUN_RENDER_INTERVAL_MS = 100;
// The whole-map view ignores the outermost points on each axis: a few stray points would shrink the rest.
const WHOLE_MAP_QUANTILE = 0.02;

export class MapView {
  constructor(parent, stats, { follow }) {
    this.stats = stats;
    this.host = element('div', { className: 'map-canvas' });
    this.followBox = element('input');
    this.followBox.type = 'checkbox';
    this.followBox.checked = follow;
    this.followBox.addEventListener('change', () => { this.poseChanged = true; });
    const wholeMapButton = element('button', { text: 'Whole map', title: 'Look at every point held' });
    wholeMapButton.addEventListener('click', () => this.showWholeMap());
    this.legend = element('ul', { className: 'legend' });
    // The dense map's entry in the legend, with the box that shows or hides it: kept across legend redraws, so the
    // box keeps its state; in the legend once a dense map came.
    this.denseBox = element('input');
    this.denseBox.type = 'checkbox';
    this.denseBox.checked = true;
    this.denseBox.id = 'dense-map-toggle';
    this.denseBox.addEventListener('change', () => {
      this.denseMesh.mesh.visible = this.denseBox.checked;
      this.needsRender = true;
    });
    this.denseText = element('span');
    this.denseItem = element('li', { title: 'The dense map of the static world (mesh), made small enough to show' }, [
      element('label', {}, [this.denseBox, ' ', this.denseText]),
    ]);
    const toolbar = element('div', { className: 'map-toolbar' }, [
      element('label', { title: 'Keep the current camera in the middle of the view' }, [
        this.followBox, ' follow camera',
      ]),
      wholeMapButton,
    ]);
    parent.append(element('section', { className: 'panel map-panel' }, [this.host, toolbar, this.legend]));

    this.pointCloud = new PointCloud();
    this.denseMesh = new DenseMesh();
    this.keyframeGraph = new KeyframeGraph();
    this.currentCamera = boldLines({ color: CURRENT_CAMERA_COLOUR }, CURRENT_CAMERA_WIDTH);
    this.scene = new Scene();
    this.scene.background = BACKGROUND_COLOUR;
    this.scene.add(this.denseMesh.mesh, this.pointCloud.points, this.keyframeGraph.group, this.currentCamera);
    this.viewCamera = new PerspectiveCamera(60, 1, 0.01, 1000); // the eye the map is seen with
    this.viewCamera.up.set(0, -1, 0);
    this.viewCamera.position.copy(VIEW_OFFSET);
    this.currentFrustum = new FrustumShape(PLACEHOLDER_CAMERA, CURRENT_CAMERA_DEPTH);

    this.mainMap = 0;
    this.maps = [];
    this.legendChanged = true;
    this.pose = null; // the newest frame's T_wc; null while not tracked
    this.lastPose = null; // the last tracked pose, drawn greyed while tracking is lost
    this.poseChanged = false;
    this.needsRender = true;
    this.viewTurned = false; // the person moved the view: render now, whatever the interval
    this.following = false;
    this.lastRender = -Infinity;
    this.renderer = this.createRenderer();
  }

  /** hello's camera: the field of view of every frustum. */
  setCamera(camera) {
    this.keyframeGraph.setCamera(camera);
    this.currentFrustum = new FrustumShape(camera, CURRENT_CAMERA_DEPTH);
    this.poseChanged = true;
  }

  /** Takes a `map` message: a full one replaces everything held. */
  applyMap(message) {
    if (message.full) {
      this.pointCloud.clear();
      this.keyframeGraph.clear();
    }
    if (message.points) this.pointCloud.upsert(message.points);
    if (message.removed_points) this.pointCloud.remove(message.removed_points);
    this.keyframeGraph.apply(message);
    this.mainMap = message.main_map;
    this.pointCloud.setMainMap(message.main_map);
    this.maps = message.maps ?? this.maps;
    this.legendChanged = true;
    this.needsRender = true;
  }

  /** Takes a `dense` message: the dense map, replacing the one held. */
  setDenseMesh(message) {
    this.denseMesh.set(message);
    this.denseMesh.mesh.visible = this.denseBox.checked;
    this.legendChanged = true;
    this.needsRender = true;
  }

  /** The newest frame's pose (null when it was not tracked). */
  setCurrentPose(T_wc) {
    this.pose = T_wc;
    if (T_wc && !this.lastPose) this.legendChanged = true; // the current camera joins the legend
    if (T_wc) this.lastPose = T_wc;
    this.poseChanged = true;
  }

  /** Looks at the bulk of the points held from above and behind, and stops following the camera. */
  showWholeMap() {
    const bounds = robustBounds(this.pointCloud.heldPositions());
    if (!bounds) return;
    this.followBox.checked = false;
    const centre = bounds.min.clone().add(bounds.max).multiplyScalar(0.5);
    const size = Math.max(bounds.max.clone().sub(bounds.min).length(), 0.5);
    this.controls?.target.copy(centre);
    this.viewCamera.position.copy(centre).addScaledVector(VIEW_OFFSET.clone().normalize(), size);
    this.controls?.update();
    this.needsRender = true;
  }

  /** Called once per animation frame: brings the scene up to date and renders it if anything changed. */
  draw() {
    if (this.keyframeGraph.rebuild()) this.needsRender = true;
    if (this.poseChanged) this.drawCurrentCamera();
    if (this.legendChanged) this.drawLegend();
    this.stats.set('points', this.pointCloud.countOfMap(this.mainMap));
    this.stats.set('keyframes', this.keyframeGraph.countOfMap(this.mainMap));
    this.stats.set('maps', this.maps.length);
    this.stats.set('dense', this.denseMesh.held ? this.denseMesh.drawnTriangles() : null);
    const now = performance.now();
    if (this.needsRender && this.renderer && (this.viewTurned || now - this.lastRender >= RUN_RENDER_INTERVAL_MS)) {
      this.needsRender = false;
      this.viewTurned = false;
      this.lastRender = now;
      this.renderer.render(this.scene, this.viewCamera);
    }
  }

  drawCurrentCamera() {
    this.poseChanged = false;
    this.needsRender = true;
    const pose = this.pose ?? this.lastPose;
    if (!pose) return;
    const positions = [];
    this.currentFrustum.appendSegments(pose, positions);
    setSegments(this.currentCamera, positions);
    this.currentCamera.material.color.copy(this.pose ? CURRENT_CAMERA_COLOUR : LOST_CAMERA_COLOUR);
    if (this.followBox.checked && this.controls) {
      // Moves the view with the camera, keeping the angle and distance the person chose.
      const offset = this.viewCamera.position.clone().sub(this.controls.target);
      this.controls.target.fromArray(cameraCentre(pose));
      this.viewCamera.position.copy(this.controls.target).add(offset);
      this.following = true; // the controls' change event is then the run's, not the person's
      this.controls.update();
      this.following = false;
    }
  }

  drawLegend() {
    this.legendChanged = false;
    const mapItems = this.maps.map(({ id, keyframes, points }) => {
      const name = `map ${id}${id === this.mainMap ? ' (main)' : ''}`;
      return legendItem(cssColour(mapColour(id)),
        `${name}: ${formatCount(keyframes)} keyframes, ${formatCount(points)} points`);
    });
    // No current camera before the first tracked frame, nor in a report's map, which has no frames.
    const cameraItems = this.lastPose ? [legendItem(cssColour(CURRENT_CAMERA_COLOUR), 'current camera')] : [];
    const denseItems = this.denseMesh.held ? [this.denseItem] : [];
    setText(this.denseText, `dense map: ${formatCount(this.denseMesh.triangles)} triangles`);
    this.legend.replaceChildren(...mapItems, ...denseItems, ...cameraItems,
      legendItem(cssColour(LOOP_EDGE_COLOUR), 'loop edge'));
  }

  /** The renderer and its controls; without WebGL the panel says so and the rest of the page still works. */
  createRenderer() {
    let renderer;
    try {
      renderer = new WebGLRenderer({ antialias: true });
    } catch {
      const text = 'This browser has no WebGL: the 3D map cannot be shown.';
      this.host.append(element('p', { className: 'notice', text }));
      return null;
    }
    renderer.outputColorSpace = LinearSRGBColorSpace;
    renderer.setPixelRatio(window.devicePixelRatio);
    this.host.append(renderer.domElement);
    this.controls = new OrbitControls(this.viewCamera, renderer.domElement);
    this.controls.addEventListener('change', () => {
      this.needsRender = true;
      if (!this.following) this.viewTurned = true;
    });
    new ResizeObserver(() => this.resize(renderer)).observe(this.host);
    return renderer;
  }

  resize(renderer) {
    const width = Math.max(this.host.clientWidth, 1);
    const height = Math.max(this.host.clientHeight, 1);
    renderer.setSize(width, height, false);
    this.viewCamera.aspect = width / height;
    this.viewCamera.updateProjectionMatrix();
    this.needsRender = true;
  }
}

/** The box holding all but the outermost points on each axis; null without points. */
function robustBounds(positions) {
  const count = positions.length / 3;
  if (count === 0) return null;
  const min = new Vector3();
  const max = new Vector3();
  for (let axis = 0; axis < 3; axis += 1) {
    const values = new Float32Array(count);
    for (let i = 0; i < count; i += 1) values[i] = positions[3 * i + axis];
    values.sort();
    min.setComponent(axis, values[Math.floor(WHOLE_MAP_QUANTILE * (count - 1))]);
    max.setComponent(axis, values[Math.ceil((1 - WHOLE_MAP_QUANTILE) * (count - 1))]);
  }
  return { min, max };
}
