// Weather: the verdict (good/bad and why), the current values, and plots of the night so far
// from the console's own record of the weather module's reports.

import * as api from "../api.js";
import { h, replace, show } from "../dom.js";
import { card } from "./context.js";
import { linePlot, seconds } from "./plots.js";

// Which sensors share a plot (same units); others get one plot each.
const GROUPS = [
  ["Temperatures [°C]", ["temperature", "dew_point", "sky_temperature"]],
  ["Humidity [%]", ["humidity"]],
  ["Wind [km/h]", ["wind_speed"]],
];

export function weatherCard(ctx) {
  const verdict = h("p#weather-verdict.verdict", "—");
  const reason = h("p#weather-reason.hint");
  const table = h("table#weather-values");
  const plotsBox = h("div.plots");
  const plots = new Map();

  ctx.poll([["get_current_weather"]], (v) => {
    const report = v.get_current_weather;
    if (!report) return;
    verdict.textContent = report.good ? "good" : "bad";
    verdict.dataset.good = report.good;
    replace(table, Object.entries(report.sensors).map(([k, x]) => h("tr", h("th", k), h("td", show(x, 4)))));
  });
  ctx.onEvent("BadWeatherEvent", (f) => (reason.textContent = f.reason ? `why bad: ${f.reason}` : "bad"), ctx.name);
  ctx.onEvent("GoodWeatherEvent", () => (reason.textContent = ""), ctx.name);
  api.get(`/api/events/recent?type=BadWeatherEvent&type=GoodWeatherEvent&sender=${encodeURIComponent(ctx.name)}&limit=1`)
    .then((r) => {
      const last = r.events.at(-1);
      if (last?.event === "BadWeatherEvent") reason.textContent = `why bad: ${last.fields.reason}`;
    })
    .catch(() => {});

  async function history() {
    let samples;
    try {
      samples = (await api.get(`/api/weather/${encodeURIComponent(ctx.name)}/history`)).samples;
    } catch {
      return;
    }
    if (!samples.length) return;
    const xs = samples.map((s) => seconds(s.time));
    const present = new Set(samples.flatMap((s) => Object.keys(s.sensors)));
    const grouped = new Set(GROUPS.flatMap(([, names]) => names));
    const groups = [
      ...GROUPS.map(([title, names]) => [title, names.filter((n) => present.has(n))]),
      ...[...present].filter((n) => !grouped.has(n) && n !== "sun_altitude").sort().map((n) => [n, [n]]),
      ["Good (1) / bad (0)", ["good"]],
    ].filter(([, names]) => names.length);
    for (const [title, names] of groups) {
      if (!plots.has(title)) {
        const plot = linePlot(title, names, { height: 150 });
        plots.set(title, plot);
        plotsBox.append(plot.element);
        ctx.cleanup(() => plot.destroy());
      }
      plots.get(title).setData([xs, ...names.map((n) => samples.map((s) => (n === "good" ? Number(s.good) : s.sensors[n] ?? null)))]);
    }
  }
  history();
  const timer = setInterval(history, 10000);
  ctx.cleanup(() => clearInterval(timer));
  return card("Weather", h("div.weather-now", h("div", verdict, reason), table), plotsBox);
}
