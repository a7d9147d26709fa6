// Colours that tell the maps apart (a run starts a new map when tracking is lost in new ground). Map ids index a
// fixed palette; the current camera and the loop edges have colours no map gets.
import { Color, ColorManagement } from 'three';

// Colours are shown as given, without conversion to a linear working space: a point's rgb is its pixel's colour in
// the image, and the renderer writes it out unchanged (map-view.js sets its output colour space to match).
ColorManagement.enabled = false;

const MAP_COLOURS = ['#4ea1ff', '#3ecf8e', '#b184f5', '#ff9f43', '#2ed3d3', '#e3d35a', '#f77fbe', '#9aa5b1']
  .map((hex) => new Color(hex));

export const CURRENT_CAMERA_COLOUR = new Color('#ff2d55');
export const LOST_CAMERA_COLOUR = new Color('#8a8f98');
export const LOOP_EDGE_COLOUR = new Color('#ffd400');
export const COVISIBILITY_EDGE_COLOUR = new Color('#c8d0dc');
export const BACKGROUND_COLOUR = new Color('#14171c');

/** A map's colour (shared: read it, do not change it). */
export function mapColour(mapId) {
  return MAP_COLOURS[mapId % MAP_COLOURS.length];
}

/** The same colour for the page's CSS (the legend). */
export function cssColour(colour) {
  return `#${colour.getHexString()}`;
}
