// Playback: pause, play, one step, speed; and the line that says how the run stands. The buttons send
// `POST control`; they are off when the run cannot be steered (hello's `controllable` is false: a paced run, the
// API, a report) or while the page is not connected.
import { element, formatCount, setText } from './dom.js';

const SPEEDS = [['0.25', '0.25×'], ['0.5', '0.5×'], ['1', '1×'], ['2', '2×'], ['0', 'max']];

export class PlaybackControls {
  constructor(parent, stats) {
    this.stats = stats;
    this.pauseButton = this.button('Pause', 'Stop after the current frame', { command: 'pause' });
    this.playButton = this.button('Play', 'Go on from here', { command: 'play' });
    this.stepButton = this.button('Step', 'Track one frame, then stay paused', { command: 'step' });
    this.speedSelect = element('select', { title: 'A multiple of the recorded rate, or as fast as it goes' });
    this.speedSelect.append(...SPEEDS.map(([value, label]) => speedOption(value, label)));
    this.speedSelect.addEventListener('change', () => {
      this.send({ command: 'speed', speed: Number(this.speedSelect.value) });
    });
    this.runLine = element('span', { className: 'run-line' });
    this.error = element('span', { className: 'control-error' });
    this.playback = element('span', { className: 'playback' }, [
      this.pauseButton, this.playButton, this.stepButton, this.speedSelect,
    ]);
    parent.append(element('div', { className: 'controls' }, [this.playback, this.runLine, this.error]));
    this.controllable = false;
    this.connection = 'connecting';
    this.status = null;
    this.errorMessage = '';
    this.changed = true;
  }

  setControllable(controllable) {
    this.controllable = controllable;
    this.changed = true;
  }

  /** 'connecting', 'connected', 'reconnecting', 'closed', or 'embedded' for a report. */
  setConnection(connection) {
    this.connection = connection;
    this.changed = true;
  }

  receiveStatus(status) {
    this.status = status;
    this.changed = true;
  }

  /** Called once per animation frame. */
  draw() {
    if (!this.changed) return;
    this.changed = false;
    const status = this.status;
    const running = status?.state === 'running' && this.connection === 'connected';
    const enabled = this.controllable && running;
    this.playback.hidden = this.connection === 'embedded'; // a report's run is over: nothing to steer
    this.pauseButton.disabled = !enabled || status.paused;
    this.playButton.disabled = !enabled || !status.paused;
    this.stepButton.disabled = !enabled || !status.paused;
    this.speedSelect.disabled = !enabled;
    if (status) this.showSpeed(status.speed);
    this.stats.set('run', status?.state ?? null);
    setText(this.runLine, this.describeRun());
    setText(this.error, this.errorMessage);
  }

  describeRun() {
    const status = this.status;
    const connection = {
      connecting: 'connecting to the run…',
      reconnecting: 'connection lost, reconnecting…',
      closed: 'the run has exited',
    }[this.connection];
    if (!status || this.connection === 'connecting') return connection ?? '';
    const total = status.total_frames ? ` of ${formatCount(status.total_frames)}` : '';
    const progress = `${formatCount(status.frames_done)}${total} frames`;
    const playback = status.state === 'running' && this.controllable
      ? ` · ${status.paused ? 'paused' : 'playing'} at ${status.speed ? `${status.speed}×` : 'max speed'}`
      : '';
    return `${status.state} · ${progress}${playback}${connection ? ` · ${connection}` : ''}`;
  }

  /** Shows the run's speed, adding it to the choices when it was set to another value on the command line. */
  showSpeed(speed) {
    const value = String(speed);
    if (![...this.speedSelect.options].some((option) => option.value === value)) {
      this.speedSelect.append(speedOption(value, `${value}×`));
    }
    this.speedSelect.value = value;
  }

  button(text, title, command) {
    const button = element('button', { text, title });
    button.disabled = true;
    button.addEventListener('click', () => this.send(command));
    return button;
  }

  async send(command) {
    this.errorMessage = '';
    try {
      const response = await fetch('control', {
        method: 'POST',
        headers: { 'Content-Type': 'application/json' },
        body: JSON.stringify(command),
      });
      const answer = await response.json();
      if (!answer.ok) throw new Error(answer.error);
      this.status = { ...this.status, paused: answer.paused, speed: answer.speed };
    } catch (error) {
      this.errorMessage = `${command.command}: ${error.message}`;
    }
    this.changed = true;
  }
}

function speedOption(value, label) {
  const option = element('option', { text: label });
  option.value = value;
  return option;
}
