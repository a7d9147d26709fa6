// The few DOM helpers the panels share: every panel builds its own elements, so the page needs no markup of its
// own beyond one root element (a report can inline the bundle next to that element).

/** A new element with the given class, text and children. */
export function element(tag, { className = '', text = '', title = '' } = {}, children = []) {
  const node = document.createElement(tag);
  if (className) node.className = className;
  if (text) node.textContent = text;
  if (title) node.title = title;
  node.append(...children);
  return node;
}

/** Sets an element's text only when it changed: drawing runs every animation frame. */
export function setText(node, text) {
  if (node.textContent !== text) node.textContent = text;
}

/** "1,234" for counts; "–" for a value not known yet. */
export function formatCount(value) {
  return value === null || value === undefined ? '–' : Number(value).toLocaleString('en-US');
}

/** A legend entry: a colour swatch and its meaning. */
export function legendItem(colourCss, text) {
  const swatch = element('span', { className: 'swatch' });
  swatch.style.background = colourCss;
  return element('li', {}, [swatch, text]);
}
