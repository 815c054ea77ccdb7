// Telescope: where it points (RA/Dec, Alt/Az), moving and offsetting, park/init/stop, and the
// all-sky plot with the Moon. Each control appears only when its interface is offered.

import * as api from "../api.js";
import { h, sexagesimal, show } from "../dom.js";
import { card, messageLine, readout } from "./context.js";
import { skyPlot } from "./skyplot.js";

const num = (id, label, attrs = {}) => h("label", label, h("input", { id, type: "number", step: "any", ...attrs }));
const value = (id) => Number(document.getElementById(id).value);

export function telescopeCard(ctx) {
  const message = messageLine();
  const [raEl, setRa] = readout("RA", "tel-ra");
  const [decEl, setDec] = readout("Dec", "tel-dec");
  const [altEl, setAlt] = readout("Alt", "tel-alt");
  const [azEl, setAz] = readout("Az", "tel-az");
  const [offEl, setOff] = readout("Offsets", "tel-offsets");
  const forms = [];
  if (ctx.offers("IPointingRaDec")) {
    forms.push(h("div.row", num("tel-move-ra", "RA [°] "), num("tel-move-dec", "Dec [°] "),
      ctx.action("Move RA/Dec", "move_radec", () => [value("tel-move-ra"), value("tel-move-dec")], { message, id: "tel-move-radec" })));
  }
  if (ctx.offers("IPointingAltAz")) {
    forms.push(h("div.row", num("tel-move-alt", "Alt [°] "), num("tel-move-az", "Az [°] "),
      ctx.action("Move Alt/Az", "move_altaz", () => [value("tel-move-alt"), value("tel-move-az")], { message, id: "tel-move-altaz" })));
  }
  if (ctx.offers("IOffsetsRaDec")) {
    forms.push(h("div.row", num("tel-off-ra", "ΔRA [″] ", { value: 0 }), num("tel-off-dec", "ΔDec [″] ", { value: 0 }),
      ctx.action("Offset RA/Dec", "set_offsets_radec", () => [value("tel-off-ra") / 3600, value("tel-off-dec") / 3600], { message, id: "tel-offset-radec" })));
  }
  if (ctx.offers("IOffsetsAltAz")) {
    forms.push(h("div.row", num("tel-off-alt", "ΔAlt [″] ", { value: 0 }), num("tel-off-az", "ΔAz [″] ", { value: 0 }),
      ctx.action("Offset Alt/Az", "set_offsets_altaz", () => [value("tel-off-alt") / 3600, value("tel-off-az") / 3600], { message, id: "tel-offset-altaz" })));
  }
  const sky = skyPlot();
  const caption = h("figcaption#sky-caption", "where it points; the Moon and the Sun");
  ctx.poll([["get_radec"], ["get_altaz"], ["get_offsets_radec"], ["get_offsets_altaz"]], (v) => {
    if (v.get_radec) {
      setRa(sexagesimal(v.get_radec[0], true));
      setDec(sexagesimal(v.get_radec[1]));
    }
    if (v.get_altaz) {
      setAlt(`${show(v.get_altaz[0], 5)}°`);
      setAz(`${show(v.get_altaz[1], 5)}°`);
      sky.telescope(v.get_altaz[0], v.get_altaz[1]);
    }
    const off = v.get_offsets_radec || v.get_offsets_altaz;
    if (off) setOff(`${show(off[0] * 3600, 3)}″, ${show(off[1] * 3600, 3)}″`);
  });
  let skyTimer = null;
  async function pollSky() {
    try {
      const s = await api.get("/api/sky");
      sky.moon(s.moon.alt, s.moon.az, s.moon.illumination);
      sky.sun(s.sun.alt, s.sun.az);
      caption.textContent = `Moon ${show(s.moon.alt, 3)}° high, ${Math.round(100 * s.moon.illumination)} % lit; Sun ${show(s.sun.alt, 3)}°`;
    } catch {
      /* no site configured: the plot shows the telescope only */
    }
    skyTimer = setTimeout(pollSky, 30000);
  }
  pollSky();
  ctx.cleanup(() => clearTimeout(skyTimer));
  return card("Telescope",
    h("div.split",
      h("div",
        h("div.readouts", raEl, decEl, altEl, azEl, ctx.offers("IOffsetsRaDec") || ctx.offers("IOffsetsAltAz") ? offEl : null),
        forms, message),
      h("figure.sky", sky.element, caption)));
}
