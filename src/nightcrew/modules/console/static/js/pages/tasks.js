// Tasks: the task archive's tasks with tonight's plan beside them (when each is next planned, or
// why it is left out), adding a task and cancelling one. Everyone sees; operators change.

import * as api from "../api.js";
import { duration, h, replace, show } from "../dom.js";
import { on } from "../live.js";
import { isOperator } from "../store.js";
import { taskForm } from "./taskform.js";

// Changes made elsewhere (`nightcrew tasks add` in another process) are found by this poll.
const REFRESH_MS = 10000;
const TASK_EVENTS = new Set(["TasksChangedEvent", "TaskStartedEvent", "TaskFinishedEvent", "TaskFailedEvent"]);

/** An ISO time as "2026-11-10 22:41" (UTC). */
const utc = (iso) => (iso ? iso.slice(0, 16).replace("T", " ") : "—");

export function tasksPage(container) {
  const body = h("tbody");
  const summary = h("p#tasks-summary.hint");
  const message = h("p#tasks-message.message", { role: "status" });
  const openWhy = new Set(); // tasks whose "why not tonight" is unfolded, kept across reloads
  let confirming = null; // the task whose cancel asks for confirmation
  let listing = null;
  let loading = false;
  let again = false;

  async function load() {
    if (loading) {
      again = true;
      return;
    }
    loading = true;
    try {
      listing = await api.get("/api/tasks");
      form.prefill(listing.time, listing.tasks[0]?.telescope_class);
      if (confirming === null) render(); // not under the hands of someone typing a reason

    } catch (exc) {
      summary.textContent = exc.describe ? exc.describe() : String(exc);
    } finally {
      loading = false;
      if (again) {
        again = false;
        load();
      }
    }
  }

  function tonight(task) {
    if (task.next_start) return h("time.next", { datetime: task.next_start }, `${utc(task.next_start)} – ${utc(task.next_end).slice(11)}`);
    if (task.state === "RUNNING") return "running now";
    if (task.ended) return "—";
    const plan = listing.plan;
    const reason = task.why_not || (!plan ? "no scheduler is online" : !plan.planned_at ? "the scheduler has not planned yet" : "no reason recorded");
    const why = h("details.why", { open: openWhy.has(task.id), ontoggle: () => (why.open ? openWhy.add(task.id) : openWhy.delete(task.id)) },
      h("summary", "why not tonight?"), h("p.reason", reason));
    return h("span.not-planned", "not planned", why);
  }

  function cancelCell(task) {
    if (task.ended) return "";
    if (confirming === task.id) {
      const reason = h("input.cancel-reason", { type: "text", placeholder: "why (optional)", "aria-label": "reason" });
      return h("span.buttons",
        reason,
        h("button.cancel-confirm", { onclick: () => cancel(task, reason.value) }, "Cancel task"),
        h("button.cancel-keep", { onclick: () => { confirming = null; render(); } }, "Keep"));
    }
    const button = h("button.cancel", { onclick: () => { confirming = task.id; render(); } }, "Cancel…");
    button.disabled = !isOperator();
    if (!isOperator()) button.title = "viewers may not cancel tasks";
    return button;
  }

  async function cancel(task, reason) {
    message.className = "message";
    try {
      const answer = await api.post(`/api/tasks/${encodeURIComponent(task.id)}/cancel`, reason ? { reason } : {});
      message.textContent = `task ${task.id} (${task.name}): ${answer.task.state}`;
    } catch (exc) {
      message.className = "message error";
      message.textContent = exc.describe();
    }
    confirming = null;
    load();
  }

  function render() {
    const { plan, tasks } = listing;
    summary.textContent = `${tasks.length} tasks; ` + (!plan ? "no scheduler is online" : plan.planned_at ? `${plan.module} planned at ${utc(plan.planned_at)} UTC` : `${plan.module} has not planned yet`);
    replace(body, tasks.map((t) => h("tr", { dataset: { task: t.id, state: t.state } },
      h("td", t.id),
      h("td.name", t.name, h("small", ` ${t.proposal}`)),
      h("td.state", h("span.task-state", t.state), t.reason ? h("small.reason", ` ${t.reason}`) : ""),
      h("td", show(t.priority)),
      h("td.windows", t.windows.map((w) => h("div", `${utc(w.start)} – ${utc(w.end)}`))),
      h("td", t.configurations.map((c) => (c.target ? `${c.type} ${c.target}` : c.type)).join(", ")),
      h("td", duration(t.duration_s)),
      h("td.tonight", tonight(t)),
      h("td.actions", cancelCell(t)))));
  }

  const form = taskForm(() => load());
  const stopEvents = on("event", (msg) => TASK_EVENTS.has(msg.event) && load());
  const stopRobotic = on("robotic", (msg) => {
    const planned = msg.scheduler?.plan?.planned_at ?? null;
    if (listing && planned !== (listing.plan?.planned_at ?? null)) load();
  });
  const timer = setInterval(load, REFRESH_MS);
  container.append(h("section.tasks",
    h("h2", "Tasks"),
    summary,
    h("table#tasks-table", h("thead", h("tr", ["id", "name", "state", "priority", "windows (UTC)", "does", "takes", "tonight (UTC)", ""].map((t) => h("th", t)))), body),
    message,
    form.element));
  load();
  return () => {
    clearInterval(timer);
    stopEvents();
    stopRobotic();
  };
}
