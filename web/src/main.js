// hoidslam's viewer page: builds the panels, feeds them the run's messages (live, or embedded by a report), and
// draws once per animation frame. Messages only store what they bring; drawing reads the newest of it, so a busy
// tab skips frames instead of queueing them. Embedded data without a frame (a run report's map) gets the map panel
// alone: there is no frame to show.
import './viewer.css';
import { connectToRun, readEmbeddedData, replayEmbedded } from './connection.js';
import { PlaybackControls } from './controls.js';
import { element, setText } from './dom.js';
import { FramePanel } from './frame-panel.js';
import { MapView } from './map-view.js';
import { Stats } from './stats.js';

function start() {
  const root = document.getElementById('hoidslam-viewer') ?? document.body.appendChild(element('div'));
  root.classList.add('hoidslam-viewer');
  const title = element('h1', { text: 'hoidslam' });
  const header = element('header', {}, [title]);
  const statsLine = element('div', { className: 'stats-line' });
  const panels = element('main', { className: 'panels' });
  root.append(header, statsLine, panels);

  const embedded = readEmbeddedData();
  const showsFrames = !embedded || Boolean(embedded.frame);
  const stats = new Stats(statsLine, { frames: showsFrames });
  const controls = new PlaybackControls(header, stats);
  const mapView = new MapView(panels, stats, { follow: !embedded });
  const framePanel = showsFrames ? new FramePanel(panels, stats) : null;
  panels.classList.toggle('map-only', !framePanel);

  const handlers = {
    hello(hello) {
      setText(title, `hoidslam · ${hello.sequence} · ${hello.version}`);
      if (!embedded) document.title = `hoidslam · ${hello.sequence}`; // a report keeps its own title
      mapView.setCamera(hello.camera);
      framePanel?.setTotalFrames(hello.total_frames);
      controls.setControllable(hello.controllable && !embedded);
    },
    map: (map) => mapView.applyMap(map),
    dense: (dense) => mapView.setDenseMesh(dense),
    frame(frame) {
      framePanel.receive(frame);
      mapView.setCurrentPose(frame.T_wc);
    },
    status: (status) => controls.receiveStatus(status),
  };
  if (embedded) {
    controls.setConnection('embedded');
    replayEmbedded(embedded, handlers);
    mapView.showWholeMap();
  } else {
    connectToRun(handlers, (connection) => controls.setConnection(connection));
  }

  const drawLoop = () => {
    mapView.draw();
    framePanel?.draw();
    controls.draw();
    requestAnimationFrame(drawLoop);
  };
  requestAnimationFrame(drawLoop);
}

if (document.readyState === 'loading') document.addEventListener('DOMContentLoaded', start);
else start();
