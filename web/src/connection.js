// Where the viewer's messages come from: the run's server-sent events, or the data a report embedded in the page.
// Either way they reach the same handlers: { hello, map, dense, frame, status }, each taking the message's object.

const EVENT_NAMES = ['hello', 'map', 'dense', 'frame', 'status'];

/** The `<script id="hoidslam-data" type="application/json">` a report embeds, parsed; null on a live page. */
export function readEmbeddedData() {
  const script = document.getElementById('hoidslam-data');
  return script ? JSON.parse(script.textContent) : null;
}

/**
 * Hands the embedded messages to the handlers once, in the order a live connection sends them. A report shows a
 * run that has ended, so a missing status reads as finished.
 */
export function replayEmbedded(data, handlers) {
  handlers.hello(data.hello);
  if (data.map) handlers.map({ ...data.map, full: true });
  if (data.dense) handlers.dense(data.dense);
  if (data.frame) handlers.frame(data.frame);
  const frames = data.hello.total_frames;
  handlers.status(data.status ?? { state: 'finished', paused: false, speed: 0, frames_done: frames,
    total_frames: frames });
}

/**
 * Listens to the run's `events` stream. EventSource reconnects by itself after a drop; the server then starts
 * again with hello and a full map. Once the run has finished, a drop means the run has exited: the page stops
 * trying then, rather than filling the console with refused connections.
 * onConnection gets 'connecting', 'connected', 'reconnecting' or 'closed'.
 */
export function connectToRun(handlers, onConnection) {
  const source = new EventSource('events');
  let finished = false;
  onConnection('connecting');
  source.addEventListener('open', () => onConnection('connected'));
  source.addEventListener('error', () => {
    if (finished) {
      source.close();
      onConnection('closed');
    } else {
      onConnection(source.readyState === EventSource.CLOSED ? 'closed' : 'reconnecting');
    }
  });
  for (const name of EVENT_NAMES) {
    source.addEventListener(name, (event) => {
      const message = JSON.parse(event.data);
      if (name === 'status') finished = message.state === 'finished';
      handlers[name](message);
    });
  }
}
