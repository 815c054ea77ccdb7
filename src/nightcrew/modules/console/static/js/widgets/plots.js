// Time-series plots with uPlot (vendored): small, fast on thousands of points, canvas-based, and
// with UTC time axes. One helper so every plot of the console looks and resizes alike.

import uPlot from "../../vendor/uplot/uPlot.esm.js";
import { h } from "../dom.js";

const COLOURS = ["#4e9af1", "#f1a14e", "#5fbf6f", "#d65f8f", "#a78bfa", "#e5d15b", "#6fd3d3"];

/** Epoch seconds of an ISO time. */
export const seconds = (iso) => Date.parse(iso) / 1000;

/**
 * A plot of series against time (or against x when ``xTime`` is false):
 * returns {element, setData([xs, ...ys]), plot}. ``options`` may add uPlot hooks, scales, axes.
 */
export function linePlot(title, labels, { height = 180, xTime = true, yLabel = "", points = false, options = {} } = {}) {
  const element = h("div.plot", { dataset: { plot: title } });
  const opts = {
    title,
    width: 400,
    height,
    tzDate: (ts) => uPlot.tzDate(new Date(ts * 1e3), "Etc/UTC"),
    scales: { x: { time: xTime } },
    axes: [
      {
        stroke: "#aab",
        grid: { stroke: "#2a3040" },
        ticks: { stroke: "#2a3040" },
        // Observatories keep UTC on a 24-hour clock, not the browser's local am/pm.
        values: xTime ? (u, splits) => splits.map((s) => new Date(s * 1000).toISOString().slice(11, 16)) : undefined,
      },
      { stroke: "#aab", grid: { stroke: "#2a3040" }, ticks: { stroke: "#2a3040" }, label: yLabel, size: 55 },
    ],
    series: [
      { label: xTime ? "UTC" : "x" },
      ...labels.map((label, i) => ({
        label,
        stroke: COLOURS[i % COLOURS.length],
        width: 1.5,
        spanGaps: false,
        points: { show: points, size: 6 },
        paths: points ? () => null : undefined,
      })),
    ],
    ...options,
  };
  const empty = [[], ...labels.map(() => [])];
  const plot = new uPlot(opts, empty, element);
  const resize = new ResizeObserver(() => {
    const width = Math.max(200, element.clientWidth);
    if (Math.abs(width - plot.width) > 2) plot.setSize({ width, height });
  });
  resize.observe(element);
  return {
    element,
    plot,
    setData(data) {
      plot.setData(data);
    },
    destroy() {
      resize.disconnect();
      plot.destroy();
    },
  };
}
