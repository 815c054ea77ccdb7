// The archive's frontend: a filter form → GET /frames/ → a table; a row → its header and related
// frames; checked rows → one zip. Plain DOM, no build step; values are set as text, never as HTML.

const form = document.getElementById("filters");
const rows = document.getElementById("rows");
const errorBox = document.getElementById("error");
const zipButton = document.getElementById("zip");
const selectAll = document.getElementById("select-all");
let page = { next: null, previous: null };

function el(tag, text, attributes = {}) {
  const node = document.createElement(tag);
  if (text !== undefined && text !== null) node.textContent = String(text);
  for (const [key, value] of Object.entries(attributes)) node.setAttribute(key, value);
  return node;
}

function showError(message) {
  errorBox.textContent = message;
  errorBox.hidden = !message;
}

async function getJson(url) {
  const response = await fetch(url);
  const body = await response.json();
  if (!response.ok) throw new Error(body.detail || `HTTP ${response.status}`);
  return body;
}

function searchUrl() {
  const params = new URLSearchParams();
  for (const [key, value] of new FormData(form)) if (String(value).trim()) params.set(key, String(value).trim());
  return `/frames/?${params}`;
}

async function load(url) {
  showError("");
  try {
    const body = await getJson(url);
    page = body;
    render(body);
    const query = new URL(url, location.href).search;
    history.replaceState(null, "", query ? `/${query}` : "/");
  } catch (error) {
    showError(error.message);
  }
}

function render(body) {
  rows.replaceChildren();
  document.getElementById("count").textContent = `${body.count} frame${body.count === 1 ? "" : "s"}`;
  for (const frame of body.results) {
    const row = el("tr", null, { "data-id": frame.id });
    const check = el("input", null, { type: "checkbox", "aria-label": `Select ${frame.basename}` });
    check.value = frame.id;
    check.addEventListener("change", updateZip);
    const thumbnail = el("img", null, { src: `${frame.thumbnail_url}?size=96`, alt: `Preview of ${frame.basename}`, loading: "lazy", width: "96" });
    const name = el("button", frame.basename, { type: "button", class: "link" });
    name.addEventListener("click", () => showDetails(frame));
    const download = el("a", "FITS", { href: frame.url, download: frame.basename });
    const cells = [check, thumbnail, name, frame.DATE_OBS, frame.OBJECT ?? "", frame.FILTER ?? "", frame.IMAGETYP, `${frame.EXPTIME} s`, frame.RLEVEL, download];
    for (const cell of cells) {
      const td = el("td");
      if (cell instanceof Node) td.append(cell); else td.textContent = String(cell);
      row.append(td);
    }
    rows.append(row);
  }
  document.getElementById("next").disabled = !body.next;
  document.getElementById("previous").disabled = !body.previous;
  selectAll.checked = false;
  updateZip();
}

function selectedIds() {
  return [...rows.querySelectorAll("input[type=checkbox]:checked")].map((box) => box.value);
}

function updateZip() {
  const ids = selectedIds();
  zipButton.disabled = ids.length === 0;
  zipButton.textContent = ids.length ? `Download selected (zip, ${ids.length})` : "Download selected (zip)";
}

async function showDetails(frame) {
  showError("");
  try {
    const [headers, related] = await Promise.all([getJson(frame.headers_url), getJson(frame.related_url)]);
    document.getElementById("details-title").textContent = frame.basename;
    const list = document.getElementById("related");
    list.replaceChildren();
    if (!related.length) list.append(el("li", "none"));
    for (const other of related) {
      const item = el("li", `${other.relation}: `);
      const link = el("button", other.basename, { type: "button", class: "link" });
      link.addEventListener("click", () => showDetails(other));
      item.append(link);
      list.append(item);
    }
    const body = document.querySelector("#header tbody");
    body.replaceChildren();
    for (const [key, value, comment] of headers.cards) {
      const row = el("tr");
      row.append(el("th", key), el("td", value === null ? "" : JSON.stringify(value)), el("td", comment));
      body.append(row);
    }
    document.getElementById("details").hidden = false;
  } catch (error) {
    showError(error.message);
  }
}

form.addEventListener("submit", (event) => {
  event.preventDefault();
  load(searchUrl());
});
form.addEventListener("reset", () => setTimeout(() => load("/frames/"), 0));
document.getElementById("next").addEventListener("click", () => page.next && load(page.next));
document.getElementById("previous").addEventListener("click", () => page.previous && load(page.previous));
selectAll.addEventListener("change", () => {
  for (const box of rows.querySelectorAll("input[type=checkbox]")) box.checked = selectAll.checked;
  updateZip();
});
zipButton.addEventListener("click", () => {
  const link = el("a", null, { href: `/frames/zip/?frame_ids=${selectedIds().join(",")}`, download: "frames.zip" });
  document.body.append(link);
  link.click();
  link.remove();
});

// A shared link (/?OBJECT=M%2013) fills the form and searches.
const initial = new URLSearchParams(location.search);
for (const [key, value] of initial) if (form.elements[key]) form.elements[key].value = value;
load(`/frames/?${initial}`);
