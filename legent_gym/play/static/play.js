// legent-gym play: the page. Frames arrive as binary JPEG messages, everything else as JSON.
"use strict";
(function () {
  const $ = (id) => document.getElementById(id);
  const token = new URLSearchParams(location.search).get("token") || "";
  const scheme = location.protocol === "https:" ? "wss:" : "ws:";
  const ws = new WebSocket(`${scheme}//${location.host}/ws?token=${encodeURIComponent(token)}`);
  ws.binaryType = "blob";
  const view = $("view"), viewCtx = view.getContext("2d");
  const mapCanvas = $("map"), mapCtx = mapCanvas.getContext("2d");
  const mapImage = new Image();
  let map = null, state = null, role = "user";
  let frames = 0, fpsCount = 0, fpsSince = performance.now();
  // Read by tests and tools: what the page has drawn.
  window.play = { frames: 0, fps: 0, state: null, map: null, errors: [], connected: false };

  function send(message) {
    if (ws.readyState === WebSocket.OPEN) ws.send(JSON.stringify(message));
  }

  ws.onopen = () => { $("connection").textContent = "connected"; $("connection").className = "good"; window.play.connected = true; };
  ws.onclose = () => { $("connection").textContent = "disconnected"; $("connection").className = "bad"; window.play.connected = false; };
  ws.onmessage = (event) => {
    if (typeof event.data !== "string") { drawFrame(event.data); return; }
    const message = JSON.parse(event.data);
    if (message.type === "hello") {
      role = message.role;
      view.width = message.width; view.height = message.height;
      $("who").textContent = role === "user" ? "you are the user" : "you are the agent";
    } else if (message.type === "map") {
      map = message; window.play.map = message;
      mapCanvas.width = message.width; mapCanvas.height = message.height;
      mapImage.onload = drawMap;
      mapImage.src = message.png;
    } else if (message.type === "state") {
      showState(message);
    } else if (message.type === "error") {
      window.play.errors.push(message.message);
      $("error").textContent = message.message;
    }
  };

  function drawFrame(blob) {
    createImageBitmap(blob).then((bitmap) => {
      viewCtx.drawImage(bitmap, 0, 0, view.width, view.height);
      bitmap.close();
      frames += 1; fpsCount += 1;
      window.play.frames = frames;
      const now = performance.now();
      if (now - fpsSince >= 1000) {
        window.play.fps = fpsCount * 1000 / (now - fpsSince);
        $("fps").textContent = `${window.play.fps.toFixed(1)} fps`;
        fpsCount = 0; fpsSince = now;
      }
      send({ type: "ack" });
    }).catch(() => send({ type: "ack" }));
  }

  function px(x, y) {
    return [(x - map.x0) * map.scale + map.pad, (map.y1 - y) * map.scale + map.pad];
  }

  // A person seen from above (as legent_gym.world.topdown_map draws them): an ellipse
  // across the shoulders, the head, a nose, and an arrow along the heading.
  function marker(pose, colour, label) {
    if (!pose) return;
    const [u, v] = px(pose[0], pose[1]);
    const yaw = pose[2] * Math.PI / 180;
    const fu = Math.cos(yaw), fv = -Math.sin(yaw);  // forward on the canvas (its y points down)
    const s = map.scale;
    mapCtx.fillStyle = colour; mapCtx.strokeStyle = colour; mapCtx.lineWidth = 3;
    mapCtx.beginPath();
    mapCtx.ellipse(u, v, Math.max(3, 0.22 * s), Math.max(2, 0.11 * s), Math.atan2(fv, fu) + Math.PI / 2, 0, 2 * Math.PI);
    mapCtx.fill();
    mapCtx.fillStyle = "#282828";
    mapCtx.beginPath(); mapCtx.arc(u, v, Math.max(2, 0.1 * s), 0, 2 * Math.PI); mapCtx.fill();
    mapCtx.beginPath(); mapCtx.arc(u + 0.1 * s * fu, v + 0.1 * s * fv, Math.max(1, 0.03 * s), 0, 2 * Math.PI); mapCtx.fill();
    mapCtx.beginPath(); mapCtx.moveTo(u + 0.15 * s * fu, v + 0.15 * s * fv);
    mapCtx.lineTo(u + 0.6 * s * fu, v + 0.6 * s * fv); mapCtx.stroke();
    const r = Math.max(4, 0.25 * s);
    mapCtx.fillStyle = "#222"; mapCtx.font = "11px sans-serif";
    mapCtx.fillText(label, u + r + 2, v + r + 8);
  }

  function drawMap() {
    if (!map || !mapImage.complete) return;
    mapCtx.drawImage(mapImage, 0, 0);
    if (state) {
      marker(state.agent_pose, "rgb(40,110,220)", role === "agent" ? "agent (you)" : "agent");
      marker(state.user_pose, "rgb(40,170,70)", role === "user" ? "user (you)" : "user");
    }
  }

  function showState(s) {
    state = s; window.play.state = s;
    $("task").textContent = `${s.task} (${s.env_id}, seed ${s.seed})`;
    $("success").textContent = s.success ? "yes" : (s.done ? "no (episode over)" : "not yet");
    $("success").className = s.success ? "good" : "";
    $("actions").textContent = `${s.actions_used} / ${s.actions_cap}`;
    $("result").textContent = s.result || "—";
    $("error").textContent = s.error;
    $("partner-error").textContent = s.partner_error;
    $("recorded").textContent = s.recorded ? `recorded as trajectory ${s.recorded}` : "";
    $("instruction").textContent = role === "user"
      ? `Ask the agent: “${s.instruction}”` : `The user asks: “${s.instruction}”`;
    const box = $("transcript");
    box.replaceChildren(...s.transcript.map((line) => {
      const div = document.createElement("div"); div.className = "line";
      const who = document.createElement("span"); who.className = `who who-${line.who}`;
      who.textContent = line.who === "you" ? `you (${role})` : line.who;
      const text = document.createElement("span"); text.textContent = line.text;
      div.append(who, text); return div;
    }));
    box.scrollTop = box.scrollHeight;
    drawMap();
  }

  const KEYS = {
    w: "forward", arrowup: "forward", a: "left", arrowleft: "left", d: "right", arrowright: "right",
    s: "around", arrowdown: "around", r: "look_up", pageup: "look_up", f: "look_down", pagedown: "look_down",
    e: "interact", x: "finish",
  };
  document.addEventListener("keydown", (event) => {
    const chat = $("chat-input");
    if (document.activeElement === chat) {
      if (event.key === "Escape") { chat.blur(); view.focus(); }
      return;
    }
    if (event.target instanceof HTMLButtonElement && (event.key === "Enter" || event.key === " ")) return;
    const key = event.key.toLowerCase();
    if (event.key === "Enter") { event.preventDefault(); chat.focus(); return; }
    if (event.key === " ") { event.preventDefault(); send({ type: "wait" }); return; }
    if (event.repeat) return;
    let name = KEYS[key];
    if (!name) return;
    if (name === "forward" && event.shiftKey) name = "forward_far";
    event.preventDefault();
    send({ type: "key", key: name });
  });

  let dragY = null;
  view.addEventListener("mousedown", (event) => { dragY = event.clientY; view.focus(); });
  window.addEventListener("mouseup", () => { dragY = null; });
  window.addEventListener("mousemove", (event) => {
    if (dragY === null) return;
    const dy = event.clientY - dragY;
    if (Math.abs(dy) >= 40) { send({ type: "key", key: dy > 0 ? "look_down" : "look_up" }); dragY = event.clientY; }
  });

  $("chat").addEventListener("submit", (event) => {
    event.preventDefault();
    const input = $("chat-input");
    const text = input.value.trim();
    if (text) send({ type: "say", text: text });
    input.value = "";
    view.focus();  // Enter sends and gives the keys back to the view
  });
  // After a click the keys go back to the view.
  $("reset-new").addEventListener("click", () => { send({ type: "reset", same_house: false }); view.focus(); });
  $("reset-same").addEventListener("click", () => { send({ type: "reset", same_house: true }); view.focus(); });
  $("show-instruction").addEventListener("click", () => { $("instruction").hidden = !$("instruction").hidden; view.focus(); });
  view.focus();
})();
