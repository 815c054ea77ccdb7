// An all-sky plot: zenith in the middle, the horizon as the rim, north up and east left (the sky as
// seen from below). Marks the telescope (with its recent track), the Moon and the Sun.

const NS = "http://www.w3.org/2000/svg";
const R = 100;

function el(tag, attrs = {}, text = null) {
  const node = document.createElementNS(NS, tag);
  for (const [k, v] of Object.entries(attrs)) node.setAttribute(k, v);
  if (text !== null) node.textContent = text;
  return node;
}

/** (alt, az) in degrees → SVG x, y; below the horizon is clamped to the rim. */
export function project(alt, az) {
  const r = (R * (90 - Math.max(alt, 0))) / 90;
  const a = (az * Math.PI) / 180;
  return [-r * Math.sin(a), -r * Math.cos(a)];
}

export function skyPlot() {
  const svg = el("svg", { viewBox: "-115 -115 230 230", class: "skyplot", role: "img", "aria-label": "all-sky plot" });
  svg.append(el("circle", { r: R, class: "sky" }));
  for (const alt of [30, 60]) svg.append(el("circle", { r: (R * (90 - alt)) / 90, class: "grid" }));
  for (const az of [0, 45, 90, 135]) {
    const [x, y] = project(0, az);
    svg.append(el("line", { x1: x, y1: y, x2: -x, y2: -y, class: "grid" }));
  }
  for (const [label, az] of [["N", 0], ["E", 90], ["S", 180], ["W", 270]]) {
    const [x, y] = project(-8, az).map((v) => v * 1.09);
    svg.append(el("text", { x, y: y + 3, class: "compass" }, label));
  }
  const track = el("polyline", { class: "track", points: "" });
  const moon = el("g", { class: "moon", visibility: "hidden" });
  moon.append(el("circle", { r: 6 }), el("text", { x: 9, y: 3 }, "Moon"));
  const sun = el("g", { class: "sun", visibility: "hidden" });
  sun.append(el("circle", { r: 6 }), el("text", { x: 9, y: 3 }, "Sun"));
  const scope = el("g", { class: "telescope", visibility: "hidden", id: "sky-telescope" });
  scope.append(el("circle", { r: 5 }), el("line", { x1: -9, y1: 0, x2: 9, y2: 0 }), el("line", { x1: 0, y1: -9, x2: 0, y2: 9 }));
  svg.append(track, sun, moon, scope);
  const points = [];

  function place(node, alt, az) {
    if (alt === null || alt === undefined || alt < 0) {
      node.setAttribute("visibility", "hidden");
      return;
    }
    const [x, y] = project(alt, az);
    node.setAttribute("transform", `translate(${x.toFixed(2)} ${y.toFixed(2)})`);
    node.setAttribute("visibility", "visible");
  }
  return {
    element: svg,
    telescope(alt, az) {
      place(scope, alt, az);
      scope.dataset.alt = alt;
      scope.dataset.az = az;
      if (alt >= 0) {
        points.push(project(alt, az).map((v) => v.toFixed(1)).join(","));
        if (points.length > 600) points.shift();
        track.setAttribute("points", points.join(" "));
      }
    },
    moon(alt, az, illumination) {
      place(moon, alt, az);
      moon.querySelector("text").textContent = `Moon ${Math.round(100 * (illumination ?? 0))} %`;
    },
    sun(alt, az) {
      place(sun, alt, az);
    },
  };
}
