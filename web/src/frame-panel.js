// The newest frame: its image with the keypoints kept (green) and dropped (red), the detector's boxes with their
// captions, and what tracking made of it. Frames arrive faster than a slow tab can decode them: only the newest
// is decoded, one at a time, and frames in between are skipped.
import { element, formatCount, legendItem, setText } from './dom.js';
import { PLACEHOLDER_CAMERA } from './pose.js';

const KEPT_COLOUR = '#30d158';
const DROPPED_COLOUR = '#ff3b30';
const DYNAMIC_BOX_COLOUR = '#ff3b30';
const STATIC_BOX_COLOUR = '#b8c0cc';
const KEYPOINT_SIZE = 3; // pixels of the image
const STAGE_COLOURS = { load: '#8e8e93', extract: '#0a84ff', detect: '#bf5af2', filter: '#ff9f0a', track: '#30d158' };
const OTHER_STAGE_COLOUR = '#64d2ff';

export class FramePanel {
  constructor(parent, stats) {
    this.stats = stats;
    this.canvas = element('canvas', { className: 'frame-canvas' });
    this.canvas.width = PLACEHOLDER_CAMERA.width;
    this.canvas.height = PLACEHOLDER_CAMERA.height;
    this.tracking = element('p', { className: 'tracking' });
    this.matching = element('p');
    this.boxes = element('p');
    this.timingBar = element('div', { className: 'timing-bar' });
    this.timingLegend = element('ul', { className: 'timing-legend' });
    parent.append(element('section', { className: 'panel frame-panel' }, [
      this.canvas,
      element('div', { className: 'frame-info' }, [
        this.tracking, this.matching, this.boxes, this.timingBar, this.timingLegend,
      ]),
    ]));
    this.totalFrames = 0;
    this.newest = null; // the newest frame received
    this.decoding = null; // the frame whose image is being decoded
    this.ready = null; // { frame, image } decoded and waiting for the next animation frame
    this.updates = 0; // frames drawn so far
  }

  setTotalFrames(totalFrames) {
    this.totalFrames = totalFrames;
  }

  /** Keeps the frame as the newest; it is drawn at the next chance, unless a newer one arrives first. */
  receive(frame) {
    this.newest = frame;
  }

  /** Called once per animation frame. */
  draw() {
    if (this.ready) {
      const { frame, image } = this.ready;
      this.ready = null;
      this.paint(frame, image);
    }
    if (this.newest && !this.decoding) {
      this.decoding = this.newest;
      this.newest = null;
      decodeImage(this.decoding.image).then((image) => {
        this.ready = { frame: this.decoding, image };
        this.decoding = null;
      });
    }
  }

  paint(frame, image) {
    this.drawImage(frame, image);
    this.drawKeypoints(frame);
    this.drawBoxes(frame);
    this.showTracking(frame);
    this.showTimings(frame.times ?? {});
    this.updates += 1;
    this.stats.set('frame', frame.index);
    this.stats.set('state', frame.state);
    this.stats.set('kept', frame.kept);
    this.stats.set('dropped', frame.dropped);
    this.stats.set('updates', this.updates);
  }

  drawImage(frame, image) {
    const width = frame.width || image?.naturalWidth || this.canvas.width;
    const height = frame.height || image?.naturalHeight || this.canvas.height;
    if (this.canvas.width !== width) this.canvas.width = width;
    if (this.canvas.height !== height) this.canvas.height = height;
    const context = this.canvas.getContext('2d');
    if (image) {
      context.drawImage(image, 0, 0, width, height);
    } else {
      context.fillStyle = '#000';
      context.fillRect(0, 0, width, height);
    }
  }

  drawKeypoints({ keypoints = [], keep = [] }) {
    const context = this.canvas.getContext('2d');
    const half = KEYPOINT_SIZE / 2;
    for (const [kept, colour] of [[1, KEPT_COLOUR], [0, DROPPED_COLOUR]]) {
      context.fillStyle = colour;
      context.beginPath();
      for (let i = 0; i < keep.length; i += 1) {
        if (keep[i] !== kept) continue;
        context.rect(keypoints[2 * i] - half, keypoints[2 * i + 1] - half, KEYPOINT_SIZE, KEYPOINT_SIZE);
      }
      context.fill();
    }
  }

  drawBoxes({ boxes = [] }) {
    const context = this.canvas.getContext('2d');
    const fontSize = Math.round(this.canvas.width / 48);
    context.font = `${fontSize}px sans-serif`;
    context.lineWidth = 2;
    context.textBaseline = 'top';
    for (const { box: [x, y, w, h], dynamic, caption, label, score } of boxes) {
      const colour = dynamic ? DYNAMIC_BOX_COLOUR : STATIC_BOX_COLOUR;
      context.strokeStyle = colour;
      context.strokeRect(x, y, w, h);
      const text = caption || `${label} ${Math.round(score * 100)} %`;
      const textWidth = context.measureText(text).width + 6;
      // Above the box, or inside its top when the box touches the image's top.
      const textY = y >= fontSize + 4 ? y - fontSize - 4 : y;
      context.fillStyle = colour;
      context.fillRect(x - 1, textY, textWidth, fontSize + 4);
      context.fillStyle = '#000';
      context.fillText(text, x + 2, textY + 2);
    }
  }

  showTracking(frame) {
    const words = (identifier) => identifier.replaceAll('_', ' ');
    const of = this.totalFrames ? ` of ${formatCount(this.totalFrames)}` : '';
    const problem = [frame.failure, frame.rejection].filter(Boolean).map(words).join(', ');
    setText(this.tracking, [`frame ${formatCount(frame.index)}${of}`, words(frame.state), words(frame.method), problem]
      .filter(Boolean).join(' · '));
    this.tracking.dataset.state = frame.state;
    setText(this.matching, [
      `map ${frame.map}${frame.keyframe ? ', new keyframe' : ''}`,
      `${formatCount(frame.matched)} matched, ${formatCount(frame.inliers)} inliers`,
      `${formatCount(frame.kept)} kept, ${formatCount(frame.dropped)} dropped`,
      `${frame.fps.toFixed(1)} fps`,
    ].join(' · '));
    const boxes = frame.boxes?.length ?? 0;
    const age = frame.box_age
      ? `carried from ${counted(frame.box_age.frames, 'frame')} (${frame.box_age.ms.toFixed(0)} ms) before`
      : 'the frame\'s own';
    setText(this.boxes, boxes ? `${counted(boxes, 'box', 'boxes')}, ${age}` : 'no boxes');
  }

  /** Each stage's share of the frame's time as one stacked bar, with the milliseconds beneath. */
  showTimings(times) {
    const stages = Object.entries(times);
    const total = stages.reduce((sum, [, ms]) => sum + ms, 0);
    const colourOf = (stage) => STAGE_COLOURS[stage] ?? OTHER_STAGE_COLOUR;
    this.timingBar.replaceChildren(...stages.map(([stage, ms]) => {
      const segment = element('span', { title: `${stage} ${ms.toFixed(1)} ms` });
      segment.style.width = `${total > 0 ? (100 * ms) / total : 0}%`;
      segment.style.background = colourOf(stage);
      return segment;
    }));
    const items = stages.map(([stage, ms]) => legendItem(colourOf(stage), `${stage} ${ms.toFixed(1)}`));
    this.timingLegend.replaceChildren(...items, element('li', { text: `= ${total.toFixed(1)} ms` }));
  }
}

/** "1 frame", "2 frames". */
function counted(count, singular, plural = `${singular}s`) {
  return `${formatCount(count)} ${count === 1 ? singular : plural}`;
}

/** The frame's JPEG (a data: URL) decoded; null when there is none or it cannot be decoded. */
async function decodeImage(source) {
  if (!source) return null;
  const image = new Image();
  image.src = source;
  try {
    await image.decode();
    return image;
  } catch {
    return null;
  }
}
