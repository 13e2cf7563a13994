// The page of `yokai serve`: draws what the server sends and sends back action indices.
// The server checks every action against the rules; the page only offers legal ones.
"use strict";

const COLOURS = { red: "#d9534f", green: "#5cb85c", blue: "#428bca", yellow: "#f0c419" };
const CELL = 46;
const $ = (id) => document.getElementById(id);

const S = {
  session: null,     // an id the server issued (POST /api/sessions), kept in local storage
  game: null,        // the last game JSON from the server
  card: null,        // a card selected for MOVE
  hint: null,        // a hint slot selected for PLACE
  busy: false,       // an animation or a request is running
};

/// This browser's session: the one kept in local storage if the server knows it (it issued
/// it, and still has it), else a new one from the server.
async function openSession() {
  const kept = localStorage.getItem("yokai-session");
  if (kept) {
    const res = await fetch(`/api/summary?session=${encodeURIComponent(kept)}`);
    if (res.ok) return kept;
  }
  const { session } = await api("POST", "/api/sessions");
  localStorage.setItem("yokai-session", session);
  return session;
}

async function api(method, url, body) {
  const init = { method, headers: {} };
  if (body !== undefined) {
    init.body = typeof body === "string" ? body : JSON.stringify(body);
    init.headers["Content-Type"] = "application/json";
  }
  const res = await fetch(url, init);
  const text = await res.text();
  let data;
  try { data = JSON.parse(text); } catch { data = { error: text }; }
  if (!res.ok) throw new Error(data.error || `${res.status} ${res.statusText}`);
  return data;
}

function showError(message, where = "error") {
  const box = $(where);
  box.textContent = message || "";
  box.hidden = !message;
}

const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

// ---- drawing -------------------------------------------------------------------------

function svgEl(name, attrs, parent) {
  const el = document.createElementNS("http://www.w3.org/2000/svg", name);
  for (const [k, v] of Object.entries(attrs)) el.setAttribute(k, v);
  if (parent) parent.appendChild(el);
  return el;
}

/// Draw `board` into `svg`; `play` (optional) holds the click handlers of the acting human.
function drawBoard(svg, board, play) {
  svg.innerHTML = "";
  const g = board.grid;
  svg.setAttribute("width", g * CELL);
  svg.setAttribute("height", g * CELL);
  svg.setAttribute("viewBox", `0 0 ${g * CELL} ${g * CELL}`);
  const targets = play ? play.targets : new Map();
  for (let r = 0; r < g; r++) {
    for (let c = 0; c < g; c++) {
      const key = `${r},${c}`;
      const cell = svgEl("rect", { x: c * CELL + 1, y: r * CELL + 1, width: CELL - 2, height: CELL - 2,
        rx: 4, class: targets.has(key) ? "cell target" : "cell", "data-cell": key }, svg);
      if (targets.has(key)) cell.addEventListener("click", () => play.act(targets.get(key)));
    }
  }
  const lastName = board.last_action ? board.last_action.name : "";
  for (const card of board.cards) {
    const cls = ["card"];
    if (card.observed) cls.push("observed");
    if (play && play.clickable.has(card.id)) cls.push("clickable");
    if (play && S.card === card.id) cls.push("selected");
    if (new RegExp(`card ${card.id}(\\D|$)`).test(lastName)) cls.push("last");
    const grp = svgEl("g", { class: cls.join(" "), "data-card": card.id,
      transform: `translate(${card.col * CELL},${card.row * CELL})` }, svg);
    svgEl("rect", { x: 4, y: 4, width: CELL - 8, height: CELL - 8, rx: 6,
      fill: card.colour ? COLOURS[card.colour] : "#8a8276" }, grp);
    const label = svgEl("text", { x: CELL / 2, y: CELL / 2, fill: card.colour ? "#111" : "#fff" }, grp);
    label.textContent = card.id;
    if (card.hint !== null) {
      const hint = board.hints[card.hint];
      (hint.colours || []).forEach((c, i) =>
        svgEl("circle", { cx: 10 + i * 9, cy: 10, r: 5, fill: COLOURS[c], class: "hint-badge" }, grp));
    }
    if (play && play.clickable.has(card.id)) grp.addEventListener("click", () => play.card(card.id));
  }
}

function swatches(colours) {
  return (colours || []).map((c) => `<span class="swatch" style="background:${COLOURS[c]}" title="${c}"></span>`).join("");
}

function drawHints(board, play) {
  const box = $("hints");
  box.innerHTML = "";
  for (const h of board.hints) {
    const div = document.createElement("div");
    div.className = `hint ${h.state.replace(" ", "-")}`;
    div.dataset.slot = h.slot;
    const where = h.state === "placed" ? ` on ${h.card}` : "";
    div.innerHTML = `#${h.slot} ${h.state === "face down" ? "?" : swatches(h.colours)}${where}`;
    if (play && play.hintClickable.has(h.slot)) {
      div.classList.add("clickable");
      div.addEventListener("click", () => play.hintClick(h.slot));
    }
    if (S.hint === h.slot) div.classList.add("selected");
    box.appendChild(div);
  }
}

// ---- playing -------------------------------------------------------------------------

/// Click handlers from the legal actions of the acting human.
function controls(game) {
  const board = game.board;
  const legal = board.legal;
  const byKind = (k) => legal.filter((a) => a.kind === k);
  const play = {
    clickable: new Set(), targets: new Map(), hintClickable: new Set(),
    act: (index) => act(index),
    card: (id) => {
      if (S.hint !== null) {
        const place = legal.find((a) => a.kind === "place" && a.hint === S.hint && a.card === id);
        if (place) return act(place.index);
      }
      const observe = legal.find((a) => a.kind === "observe" && a.card === id);
      if (observe) return act(observe.index);
      S.card = S.card === id ? null : id;
      render(S.game);
    },
    hintClick: (slot) => {
      const reveal = legal.find((a) => a.kind === "reveal");
      const firstDown = board.hints.find((h) => h.state === "face down");
      if (reveal && firstDown && firstDown.slot === slot) return act(reveal.index);
      S.hint = S.hint === slot ? null : slot;
      S.card = null;
      render(S.game);
    },
  };
  for (const a of byKind("observe")) play.clickable.add(a.card);
  for (const a of byKind("move")) {
    play.clickable.add(a.card);
    if (S.card === a.card) play.targets.set(`${a.cell[0]},${a.cell[1]}`, a.index);
  }
  for (const a of byKind("place")) {
    play.hintClickable.add(a.hint);
    if (S.hint === a.hint) play.clickable.add(a.card);
  }
  const firstDown = board.hints.find((h) => h.state === "face down");
  if (byKind("reveal").length && firstDown) play.hintClickable.add(firstDown.slot);
  return play;
}

function render(game) {
  S.game = game;
  const board = game.board;
  $("curtain").hidden = !game.curtain;
  if (game.curtain) {
    $("curtain-text").textContent =
      `Pass the screen to seat ${game.to_act}. Seat ${game.to_act}: press the button when only you can see it.`;
    return;
  }
  const mine = board && !board.over && game.to_act === board.viewer && !S.busy;
  const play = mine ? controls(game) : null;
  drawBoard($("board"), board, play);
  drawHints(board, play);
  const seats = game.seats.map((n, i) => `${i}: ${n}`).join(", ");
  if (board.over) {
    const o = board.outcome;
    $("status").textContent = `Game over after ${o.length} steps: R = ${o.reward} (${o.won ? "won" : "not won"}` +
      `${o.early_end ? ", ended early" : ""}, score ${o.score}, ${o.correct_hints} correct and ${o.wrong_hints} wrong hints). Seats ${seats}.`;
  } else {
    const who = game.seats[board.turn];
    $("status").textContent = `Step ${board.step}: seat ${board.turn} (${who}) to ${board.substep_name}. ` +
      `You see seat ${board.viewer}'s view. Seats ${seats}.`;
  }
  const legal = mine ? board.legal : [];
  const end = legal.find((a) => a.kind === "end");
  const noop = legal.find((a) => a.kind === "noop");
  $("end").disabled = !end;
  $("end").onclick = end ? () => act(end.index) : null;
  $("noop").hidden = !noop;
  $("noop").disabled = !noop;
  $("noop").onclick = noop ? () => act(noop.index) : null;
  const list = $("actions");
  list.innerHTML = "";
  for (const a of legal) {
    const li = document.createElement("li");
    const b = document.createElement("button");
    b.textContent = a.name;
    b.dataset.index = a.index;
    b.addEventListener("click", () => act(a.index));
    li.appendChild(b);
    list.appendChild(li);
  }
  const log = $("log");
  log.innerHTML = "";
  for (const line of game.log) {
    const li = document.createElement("li");
    li.textContent = line;
    log.appendChild(li);
  }
  document.body.dataset.state = board.over ? "over" : mine ? "your-turn" : "waiting";
}

/// Show the boards after each step one at a time (the bots' moves), then the game.
async function animate(game) {
  const delay = Number($("speed").value);
  if (delay > 0 && game.frames.length > 1) {
    S.busy = true;
    document.body.dataset.state = "animating";
    for (const frame of game.frames.slice(0, -1)) {
      drawBoard($("board"), frame, null);
      drawHints(frame, null);
      $("status").textContent = frame.last_action
        ? `Seat ${frame.last_action.seat} played ${frame.last_action.name}.` : "";
      await sleep(delay);
    }
    S.busy = false;
  }
  render(game);
}

async function act(index) {
  if (S.busy) return;
  S.card = null;
  S.hint = null;
  showError("");
  // Until the server answers, the board on screen is the one before this action: it is not
  // the player's turn (a second click would send a second action, and a test driving the
  // page would click cards that the answer is about to replace).
  S.busy = true;
  document.body.dataset.state = "sending";
  try {
    const g = S.game;
    const next = await api("POST", `/api/games/${g.id}/actions`,
      { session: S.session, seat: g.board.viewer, action: index });
    S.busy = false;
    await animate(next);
  } catch (e) {
    S.busy = false;
    showError(e.message);
    render(S.game);
  }
}

async function newGame(event) {
  if (event) event.preventDefault();
  showError("");
  const seats = $("seats").value.split(",").map((s) => s.trim()).filter(Boolean);
  const body = { session: S.session };
  if (seats.length) body.seats = seats;
  if ($("config").value.trim()) body.config = $("config").value.trim();
  try {
    const game = await api("POST", "/api/games", body);
    history.replaceState(null, "", `?game=${game.id}`);
    S.card = S.hint = null;
    await animate(game);
  } catch (e) {
    showError(e.message);
  }
}

async function reveal() {
  try {
    render(await api("POST", `/api/games/${S.game.id}/reveal`, { session: S.session }));
  } catch (e) {
    showError(e.message);
  }
}

// ---- replays and summary -------------------------------------------------------------

let replay = null;

async function openReplay(text) {
  showError("", "replay-error");
  try {
    replay = await api("POST", "/api/replay", text);
  } catch (e) {
    showError(e.message, "replay-error");
    return;
  }
  const t = $("timeline");
  t.max = replay.frames.length - 1;
  t.value = 0;
  t.disabled = false;
  const o = replay.outcome;
  $("replay-title").textContent = `${replay.config}, seats ${replay.seats.join(", ")}` +
    (o ? `: R = ${o.reward} (${o.won ? "won" : "not won"})` : " (unfinished)");
  showFrame(0);
}

function showFrame(i) {
  const frame = replay.frames[i];
  drawBoard($("replay-board"), frame, null);
  $("replay-step").textContent = i === 0 ? "the deal"
    : `step ${i}: seat ${replay.steps[i - 1].seat} played ${replay.steps[i - 1].name}`;
}

async function showSummary() {
  const table = $("summary-table");
  try {
    const s = await api("GET", `/api/summary?session=${S.session}`);
    const m = s.metrics;
    const pct = (x) => (x === null || x === undefined ? "–" : `${(100 * x).toFixed(0)} %`);
    table.innerHTML = m
      ? `<tr><th>games</th><th>R</th><th>win rate</th><th>EE</th><th>SEE</th><th>WEE</th><th>LEN</th></tr>` +
        `<tr><td>${m.games}</td><td>${m.reward.toFixed(2)} ± ${m.reward_se.toFixed(2)}</td><td>${pct(m.win_rate)}</td>` +
        `<td>${pct(m.early_end)}</td><td>${pct(m.successful_early_end)}</td><td>${pct(m.win_given_early_end)}</td>` +
        `<td>${m.length.toFixed(1)}</td></tr>`
      : "<tr><td>No finished game yet.</td></tr>";
    if (s.unfinished) table.innerHTML += `<tr><td colspan="7">${s.unfinished} unfinished</td></tr>`;
  } catch (e) {
    table.innerHTML = `<tr><td>${e.message}</td></tr>`;
  }
}

function showTab(name) {
  for (const tab of document.querySelectorAll("nav .tab")) tab.classList.toggle("active", tab.dataset.tab === name);
  for (const id of ["play", "replay", "summary"]) $(id).hidden = id !== name;
  if (name === "summary") showSummary();
}

// ---- start ---------------------------------------------------------------------------

async function start() {
  for (const tab of document.querySelectorAll("nav .tab")) tab.addEventListener("click", () => showTab(tab.dataset.tab));
  $("new-game").addEventListener("submit", newGame);
  $("reveal").addEventListener("click", reveal);
  $("timeline").addEventListener("input", (e) => showFrame(Number(e.target.value)));
  $("replay-file").addEventListener("change", async (e) => {
    const file = e.target.files[0];
    if (file) openReplay(await file.text());
  });
  $("replay-current").addEventListener("click", async () => {
    if (!S.game) return;
    const res = await fetch(`/api/games/${S.game.id}/replay?session=${S.session}`);
    openReplay(await res.text());
  });
  S.session = await openSession();
  const defaults = await api("GET", "/api/config");
  $("seats").value = defaults.seats.join(", ");
  $("config").value = defaults.config;
  $("offered").textContent = `Seats offered: ${defaults.offered.seats.join(", ")}. ` +
    `Games offered: ${defaults.offered.configs.join(", ")}.`;
  const id = new URLSearchParams(location.search).get("game");
  if (id) {
    try {
      render(await api("GET", `/api/games/${id}?session=${S.session}`));
      return;
    } catch (e) {
      showError(`${e.message}; a new game was started`);
    }
  }
  await newGame();
}

start();
