// The night as it happens: the mastermind's action, task and reason for waiting, and the
// scheduler's plan as a timeline against the Sun's altitude and the weather verdicts.

import * as api from "../api.js";
import { clock, h, replace, show } from "../dom.js";
import { card, messageLine, readout } from "./context.js";
import { linePlot, seconds } from "./plots.js";

/** Keep ``render(body)`` fed with /api/robotic: now and on every `robotic` message. */
function followRobotic(ctx, render) {
  ctx.on("robotic", (msg) => render(msg));
  api.get("/api/robotic").then(render).catch(() => {});
}

export function mastermindCard(ctx) {
  const [actionEl, setAction] = readout("Action", "mm-action");
  const [whyEl, setWhy] = readout("Waiting for", "mm-waiting");
  const [taskEl, setTask] = readout("Task", "mm-task");
  const [condEl, setCond] = readout("Conditions", "mm-conditions");
  const description = h("p#mm-description.verdict");
  const progress = h("progress#mm-progress", { max: 1, value: 0 });
  const line = timeline("The night: plan, Sun and weather"); // the plan it follows, beside what it does
  ctx.cleanup(() => line.destroy());
  const mode = startStop(ctx);
  followRobotic(ctx, (body) => {
    line.update(body);
    const s = body.mastermind?.module === ctx.name ? body.mastermind.status : null;
    if (!s) return;
    setAction(s.running ? s.action : "stopped");
    description.textContent = s.description;
    setWhy(s.waiting_for ? `${s.waiting_for}${s.waiting_until ? ` (until ${clock(s.waiting_until)})` : ""}` : "—");
    const t = s.task;
    setTask(t ? `${t.name} (#${t.id}): ${t.exposures_done} of ${t.exposures_total} exposures, ends ${clock(t.eta)}` : "—");
    progress.max = t?.exposures_total || 1;
    progress.value = t?.exposures_done || 0;
    setCond(`Sun ${show(s.sun_altitude, 3)}°, weather ${s.weather_good === null ? "?" : s.weather_good ? "good" : "bad"}, roof ${show(s.roof)}, telescope ${s.telescope_ready ? "ready" : "not ready"}`);
  });
  return card("Mastermind", description, mode, h("div.readouts", actionEl, whyEl, taskEl, condEl), progress, line.element);
}

/** Robotic mode (IStartStop): running or stopped, and the buttons an operator starts and stops it with. */
function startStop(ctx) {
  if (!ctx.has("start")) return null;
  const [modeEl, setMode] = readout("Robotic mode", "mm-mode");
  const message = messageLine();
  message.id = "mm-message";
  const said = (text) => () => (message.textContent = text);
  const start = ctx.action("Start robotic mode", "start", () => [], { message, id: "mm-start", then: said("robotic mode started") });
  const stop = ctx.action("Stop robotic mode", "stop", () => [], { message, id: "mm-stop", then: said("robotic mode stopped: the running task is aborted, the roof closes, the telescope parks") });
  ctx.poll([["is_running"]], (v) => {
    if (v.is_running === undefined) return;
    setMode(v.is_running ? "running" : "stopped");
    modeEl.dataset.running = v.is_running;
    // Only the button that changes something; neither for a viewer.
    start.disabled = v.is_running || !ctx.can("start");
    stop.disabled = !v.is_running || !ctx.can("stop");
  });
  return h("div.robotic-mode", h("div.buttons", modeEl, start, stop), message);
}

const TASK_COLOURS = ["#4e9af1", "#5fbf6f", "#f1a14e", "#a78bfa", "#d65f8f", "#6fd3d3"];

/** The timeline: Sun altitude as a line; planned tasks as bars; bad weather shaded; now marked. */
export function timeline(title = "Plan of the night") {
  let body = null;
  const drawLayers = (u) => {
    if (!body) return;
    const { ctx } = u;
    const top = u.bbox.top;
    const height = u.bbox.height;
    const x = (iso) => u.valToPos(seconds(iso), "x", true);
    ctx.save();
    const weather = body.weather || [];
    weather.forEach((w, i) => {
      if (w.good) return;
      const end = weather[i + 1]?.time || body.time;
      ctx.fillStyle = "rgba(214, 95, 95, 0.18)";
      ctx.fillRect(x(w.time), top, x(end) - x(w.time), height);
    });
    const slots = body.scheduler?.plan?.slots || [];
    // Tasks in three lanes above the horizon line: at night the Sun's curve stays below it.
    const barHeight = Math.min(24, height / 8);
    ctx.font = `${Math.round(11 * devicePixelRatio)}px sans-serif`;
    ctx.textAlign = "left"; // uPlot leaves its axis labels' alignment on the context
    ctx.textBaseline = "alphabetic";
    slots.forEach((s, i) => {
      const x0 = Math.max(u.bbox.left, x(s.start));
      const x1 = Math.min(u.bbox.left + u.bbox.width, x(s.end));
      if (x1 <= x0) return;
      const y = top + barHeight * (0.4 + (i % 3) * 1.2);
      ctx.fillStyle = TASK_COLOURS[i % TASK_COLOURS.length];
      ctx.fillRect(x0, y, Math.max(2, x1 - x0), barHeight);
      const label = s.name || `#${s.task_id}`;
      if (ctx.measureText(label).width < x1 - x0 - 6) {
        ctx.fillStyle = "#0b0f18";
        ctx.fillText(label, x0 + 3, y + barHeight * 0.7);
      }
    });
    const now = x(body.time);
    ctx.strokeStyle = "#e5d15b";
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.moveTo(now, top);
    ctx.lineTo(now, top + height);
    ctx.stroke();
    ctx.restore();
  };
  const plot = linePlot(title, ["Sun altitude [°]"], {
    height: 240,
    yLabel: "Sun altitude [°]",
    options: { hooks: { draw: [drawLayers] }, scales: { x: { time: true }, y: { range: [-90, 90] } } },
  });
  return {
    element: plot.element,
    destroy: () => plot.destroy(),
    update(next) {
      body = next;
      const sun = next.sun || [];
      const slots = next.scheduler?.plan?.slots || [];
      const xs = sun.map((s) => seconds(s.time));
      if (!xs.length && slots.length) xs.push(seconds(slots[0].start), seconds(slots.at(-1).end));
      plot.setData([xs, sun.length ? sun.map((s) => s.altitude) : xs.map(() => null)]);
    },
  };
}

export function schedulerCard(ctx) {
  const summary = h("p#plan-summary");
  const table = h("table#plan-slots");
  const line = timeline();
  ctx.cleanup(() => line.destroy());
  followRobotic(ctx, (body) => {
    const plan = body.scheduler?.module === ctx.name ? body.scheduler.plan : null;
    line.update(body);
    if (!plan) {
      summary.textContent = "no plan yet";
      return;
    }
    summary.textContent = `${plan.solver} ${plan.status}: objective ${show(plan.objective, 5)}, bound ${show(plan.bound, 5)}, gap ${plan.gap === null ? "—" : `${show(100 * plan.gap, 3)} %`}; ${plan.slots.length} tasks, planned at ${clock(plan.planned_at)} in ${show(plan.wall_time_s, 3)} s`;
    replace(table, h("tr", h("th", "start"), h("th", "end"), h("th", "task"), h("th", "priority")),
      plan.slots.map((s) => h("tr", h("td", clock(s.start)), h("td", clock(s.end)), h("td", s.name || s.task_id), h("td", show(s.priority)))));
  });
  return card("Scheduler", summary, line.element, h("details", h("summary", "Planned tasks"), table));
}
