// Copyright 2026 The anfis_elevation_ros Authors. Licensed under the Apache License 2.0.
//
// The command centre's page: /api/state once, then the Server-Sent Events of /api/events,
// rendered as a roster, a floor selector, the plan of one floor (Leaflet, a simple CRS in
// metres: lat = y, lng = x of the map frame), a side view of the floor stack, an alarm
// banner with a tone and the event log. Writes (acknowledge, evacuate, roll call) carry the
// session token, asked once and kept in sessionStorage.
'use strict';

(function () {
  const MODES = { '-1': '\u2193 down', '0': '\u2192 level', '1': '\u2191 up' };
  const SHORT = { no_motion: 'MAN DOWN', lost_contact: 'LOST CONTACT',
    diagnostics_error: 'SENSOR ERROR', floor_unknown: 'FLOOR UNKNOWN' };
  const LOG_ROWS = 200;
  const BANNER_LINES = 3;          // more alarms than this: the roster lists them
  const PROBE_POINTS = 10000;      // latencies kept for the tests and the benchmark
  const ARROW_M = 2.0;
  const GRID_M = 5.0;

  const state = {
    seq: 0, building: null, floors: [], responders: new Map(), log: [], lastLogSeq: 0,
    params: {}, evacuation: null, rollCall: null, trackMax: 600,
  };
  // Read by the browser tests and the benchmark: latency of each new responder stamp (s, from
  // the message stamp to the end of the render that showed it), the same for `elevation`
  // messages alone, and the number of renders.
  const probe = {
    latencies: [], elevationLatencies: [], renders: 0, batches: 0, renderSeconds: 0,
    state: state,
  };
  window.commandCentre = probe;

  let selectedFloor = null;
  let selectedResponder = null;
  let renderScheduled = false;
  let pendingStamps = [];
  let pendingElevationStamps = [];
  let audio = null;
  let map = null;
  let layers = null;
  let gridBounds = null;
  let fittedOnResponders = false;
  const drawn = new Map();     // responder id -> its Leaflet layers
  const previousHtml = {};

  // -- helpers --------------------------------------------------------------------------

  function $(id) { return document.getElementById(id); }

  function escapeHtml(text) {
    return String(text).replace(/[&<>"']/g, function (c) {
      return { '&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&#39;' }[c];
    });
  }

  function setHtml(id, html) {
    if (previousHtml[id] === html) { return false; }
    previousHtml[id] = html;
    $(id).innerHTML = html;
    return true;
  }

  function utcTime(unixS) {
    return new Date(unixS * 1000).toISOString().substring(11, 19);
  }

  function floorInfo(index) {
    return state.floors.find(function (f) { return f.index === index; }) || null;
  }

  function floorName(index) {
    const f = floorInfo(index);
    return f && f.name ? f.name : 'Floor ' + index;
  }

  function floorText(r) {
    if (r.floor === null || r.floor === undefined) { return 'Floor ?'; }
    if (r.floor_certain) { return floorName(r.floor); }
    const range = r.floor_range;   // the floors the height can be on (storeys unknown)
    if (!range) { return 'Floor ?'; }
    return 'Floor ' + range[0] + (range[1] === range[0] ? '' : '\u2013' + range[1]) + '?';
  }

  function liveAge(r) {
    return r.last_update_age_s + (performance.now() - r.receivedAt) / 1000;
  }

  function ll(x, y) { return [y, x]; }

  function ordered() {
    return Array.from(state.responders.values()).sort(function (a, b) {
      return a.priority - b.priority || (a.id < b.id ? -1 : a.id > b.id ? 1 : 0);
    });
  }

  function activeAlarms() {
    const out = [];
    state.responders.forEach(function (r) {
      r.alarms.forEach(function (a) { out.push({ alarm: a, responder: r }); });
    });
    const rank = { alarm: 0, 'pre-alarm': 1 };
    return out.sort(function (p, q) {
      return (p.alarm.acknowledged - q.alarm.acknowledged) ||
        (rank[p.alarm.severity] - rank[q.alarm.severity]) || (p.alarm.raised_unix_s - q.alarm.raised_unix_s);
    });
  }

  // -- the model, from /api/state and the push stream -----------------------------------

  function takeResponder(entry, trackAppend) {
    const old = state.responders.get(entry.id);
    let track = entry.track;
    const appended = trackAppend && trackAppend.length > 0;
    if (track === undefined) {
      track = old ? (appended ? old.track.concat(trackAppend) : old.track) : (trackAppend || []);
    }
    if (track.length > state.trackMax) { track = track.slice(track.length - state.trackMax); }
    entry.track = track;
    entry.trackChanged = !old || old.trackChanged || track !== old.track;
    entry.receivedAt = performance.now();
    entry.dirty = true;
    state.responders.set(entry.id, entry);
    // An entry also comes for a floor, mode, diagnostics or alarm change: only a new stamp
    // is a message to time.
    if (isNewStamp(entry.stamp_unix_s, old && old.stamp_unix_s)) {
      pendingStamps.push(entry.stamp_unix_s);
    }
    if (isNewStamp(entry.elevation_stamp_unix_s, old && old.elevation_stamp_unix_s)) {
      pendingElevationStamps.push(entry.elevation_stamp_unix_s);
    }
  }

  function isNewStamp(stamp, oldStamp) {
    return stamp !== null && stamp !== undefined && stamp !== oldStamp;
  }

  function takeLog(entry) {
    if (entry.seq <= state.lastLogSeq) { return; }
    state.lastLogSeq = entry.seq;
    state.log.push(entry);
    if (state.log.length > LOG_ROWS) { state.log.shift(); }
  }

  function takeSnapshot(snapshot) {
    state.seq = snapshot.seq;
    state.building = snapshot.building;
    state.floors = snapshot.floors;
    state.params = snapshot.params;
    state.evacuation = snapshot.evacuation;
    state.rollCall = snapshot.roll_call;
    state.trackMax = snapshot.track_max_points;
    state.responders = new Map();
    snapshot.responders.forEach(function (r) { takeResponder(r); });
    state.log = [];
    state.lastLogSeq = 0;
    snapshot.log.forEach(takeLog);
    drawn.forEach(function (d) { d.group.remove(); });
    drawn.clear();
    if ($('title') && state.building && state.building.name) {
      $('title').textContent = 'Command centre \u2014 ' + state.building.name;
    }
  }

  function takeBatch(batch) {
    probe.batches += 1;
    for (const event of batch.events) {
      if (event.type === 'reset') { return loadState(); }
      if (event.type === 'responder') { takeResponder(event.responder, event.track_append); }
      if (event.type === 'log') { takeLog(event.entry); }
      if (event.type === 'incident') {
        state.floors = event.floors;
        state.evacuation = event.evacuation;
        state.rollCall = event.roll_call;
      }
    }
    state.seq = batch.seq;
    scheduleRender();
  }

  function loadState() {
    return fetch('/api/state', { cache: 'no-store' })
      .then(function (response) {
        if (!response.ok) { throw new Error('/api/state: HTTP ' + response.status); }
        return response.json();
      })
      .then(function (snapshot) { takeSnapshot(snapshot); scheduleRender(); });
  }

  function connect() {
    const source = new EventSource('/api/events?since=' + state.seq);
    source.addEventListener('batch', function (e) { takeBatch(JSON.parse(e.data)); });
    source.onopen = function () { setConnection(true); };
    source.onerror = function () { setConnection(false); };   // it reconnects by itself
  }

  function setConnection(up) {
    const el = $('connection');
    el.className = 'connection ' + (up ? 'up' : 'down');
    el.textContent = up ? 'live' : 'NO CONNECTION to the command centre';
  }

  // -- rendering ------------------------------------------------------------------------

  function scheduleRender() {
    if (renderScheduled) { return; }
    renderScheduled = true;
    if (document.hidden) { setTimeout(render, 0); } else { requestAnimationFrame(render); }
  }

  function render() {
    const started = performance.now();
    renderScheduled = false;
    if (selectedFloor === null) { selectedFloor = defaultFloor(); }
    renderBanner();
    renderRoster();
    renderFloors();
    renderMap();
    renderSideView();
    renderLog();
    renderStatus();
    const now = Date.now() / 1000;
    recordLatencies(probe.latencies, pendingStamps, now);
    recordLatencies(probe.elevationLatencies, pendingElevationStamps, now);
    pendingStamps = [];
    pendingElevationStamps = [];
    probe.renders += 1;
    probe.renderSeconds += (performance.now() - started) / 1000;
  }

  function recordLatencies(latencies, stamps, now) {
    stamps.forEach(function (stamp) { latencies.push(now - stamp); });
    if (latencies.length > PROBE_POINTS) { latencies.splice(0, latencies.length - PROBE_POINTS); }
  }

  function defaultFloor() {
    const first = ordered().find(function (r) { return r.floor !== null; });
    if (first) { return first.floor; }
    return state.floors.length ? state.floors[state.floors.length - 1].index : null;
  }

  function alarmChip(a) {
    const cls = a.acknowledged ? 'acknowledged' : a.severity;
    const button = a.acknowledged ? '' :
      '<button type="button" class="ack" data-alarm="' + escapeHtml(a.id) + '">Ack</button>';
    const what = (SHORT[a.kind] || a.title) + (a.severity === 'pre-alarm' ? ' (pre)' : '');
    return '<span class="chip ' + cls + '" title="' + escapeHtml(a.title + ': ' + a.text) + '">' +
      escapeHtml(what) + (a.acknowledged ? ' \u2713' : '') + button + '</span>';
  }

  function rowClass(r) {
    const open = r.alarms.filter(function (a) { return !a.acknowledged; });
    const cls = [];
    if (open.some(function (a) { return a.severity === 'alarm'; })) { cls.push('alarm'); }
    else if (open.length) { cls.push('prealarm'); }
    else if (r.alarms.length) { cls.push('acknowledged'); }
    if (r.id === selectedResponder) { cls.push('selected'); }
    return cls.join(' ');
  }

  function renderRoster() {
    const rows = ordered().map(function (r) {
      const floor = floorText(r);
      const last = r.floor_certain || r.floor === null ? '' :
        ' <small>(last ' + escapeHtml(floorName(r.floor)) + ')</small>';
      return '<tr data-id="' + escapeHtml(r.id) + '" class="' + rowClass(r) + '">' +
        '<td class="name">' + escapeHtml(r.id) + '</td>' +
        '<td class="floor' + (floor.endsWith('?') ? ' uncertain' : '') + '">' +
        escapeHtml(floor) + last + '</td>' +
        '<td class="mode">' + (MODES[r.mode] || '\u2013') + '</td>' +
        '<td class="age"></td>' +
        '<td class="quality quality-' + escapeHtml(r.data_quality) + '">' +
        escapeHtml(r.data_quality) + '</td>' +
        '<td class="alarms">' + r.alarms.map(alarmChip).join('') + '</td></tr>';
    });
    setHtml('roster-body', rows.join(''));
    $('roster-count').textContent = '(' + state.responders.size + ')';
    renderAges();
  }

  function renderAges() {
    const lost = state.params.lost_contact_s || 10;
    document.querySelectorAll('#roster tbody tr').forEach(function (row) {
      const r = state.responders.get(row.dataset.id);
      if (!r) { return; }
      const age = liveAge(r);
      const cell = row.querySelector('.age');
      const text = age < 10 ? age.toFixed(1) + ' s' : Math.round(age) + ' s';
      if (cell.textContent !== text) { cell.textContent = text; }
      cell.classList.toggle('late', age >= lost / 2);
    });
  }

  function renderBanner() {
    const open = activeAlarms().filter(function (p) { return !p.alarm.acknowledged; });
    const banner = $('alarm-banner');
    banner.hidden = open.length === 0;
    banner.classList.toggle('prealarm-only',
      open.length > 0 && open.every(function (p) { return p.alarm.severity === 'pre-alarm'; }));
    const more = open.length > BANNER_LINES ?
      '<div class="banner-more">+ ' + (open.length - BANNER_LINES) +
      ' more unacknowledged alarms: see the roster</div>' : '';
    setHtml('alarm-banner', open.slice(0, BANNER_LINES).map(function (p) {
      const a = p.alarm;
      return '<div class="banner-alarm" data-id="' + escapeHtml(p.responder.id) + '">' +
        '<span>' + (a.severity === 'alarm' ? 'ALARM' : 'PRE-ALARM') + ' \u2014 ' +
        escapeHtml(p.responder.id) + ' \u2014 ' + escapeHtml(a.title) + ': ' +
        escapeHtml(a.text) + ' (' + escapeHtml(floorText(p.responder)) + ', since ' +
        utcTime(a.raised_unix_s) + ')</span>' +
        '<button type="button" class="ack" data-alarm="' + escapeHtml(a.id) +
        '">Acknowledge</button></div>';
    }).join('') + more);
  }

  function renderFloors() {
    const html = state.floors.map(function (f) {
      const selected = f.index === selectedFloor ? ' selected' : '';
      const badge = f.alarms ? '<span class="badge" title="alarms">' + f.alarms + '\u26a0</span>' : '';
      const uncertain = f.uncertain ? ' (' + f.uncertain + ' uncertain)' : '';
      // Responders whose floor is in doubt and may be this one (their floor range).
      const possible = f.possible ? '<span class="possible">+' + f.possible + '?</span>' : '';
      const maybe = f.possible ? ', ' + f.possible + ' more may be here' : '';
      return '<button type="button" role="tab" class="floor' + selected + '" data-floor="' +
        f.index + '" title="' + f.responders + ' responders' + uncertain + maybe + '">' +
        escapeHtml(f.name || 'Floor ' + f.index) + '<span class="count">' + f.responders +
        '</span>' + possible + badge + '</button>';
    });
    const floorless = Array.from(state.responders.values())
      .filter(function (r) { return r.floor === null; }).length;
    if (floorless) {
      html.push('<span class="floorless" title="no floor message yet">No floor: ' +
        '<span class="count">' + floorless + '</span></span>');
    }
    setHtml('floors', html.join(''));
  }

  function renderStatus() {
    const parts = [];
    if (state.evacuation) {
      parts.push('EVACUATION ordered ' + utcTime(state.evacuation.ordered_unix_s) + ' by ' +
        state.evacuation.by);
    }
    if (state.rollCall) {
      parts.push('Roll call ' + utcTime(state.rollCall.taken_unix_s) + ' (' +
        state.rollCall.responders + ')');
    }
    $('incident-status').textContent = parts.join(' \u00b7 ');
  }

  function renderLog() {
    const rows = state.log.slice().reverse().map(function (e) {
      return '<tr class="' + escapeHtml(e.event.replace(/\s/g, '-')) + '"><td>' +
        escapeHtml(e.time_utc.substring(11, 19)) + '</td><td>' + escapeHtml(e.responder) +
        '</td><td><b>' + escapeHtml(e.event) + '</b> ' + escapeHtml(e.text) + '</td></tr>';
    });
    setHtml('log-body', rows.join(''));
  }

  // -- the plan of the selected floor ---------------------------------------------------

  function setUpMap() {
    map = L.map('map', { crs: L.CRS.Simple, minZoom: -4, maxZoom: 6, zoomSnap: 0.25,
      attributionControl: false });
    L.control.scale({ imperial: false, metric: true }).addTo(map);
    layers = { grid: L.layerGroup().addTo(map), plan: L.layerGroup().addTo(map),
      responders: L.layerGroup().addTo(map) };
    map.setView([0, 0], 1);
  }

  function planOf(index) {
    if (!state.building) { return null; }
    return state.building.floors.find(function (f) { return f.index === index; }) || null;
  }

  function floorBounds() {
    const points = [];
    const plan = planOf(selectedFloor);
    if (plan) { plan.outline.forEach(function (p) { points.push(p); }); }
    state.responders.forEach(function (r) {
      if (r.x_m !== null && r.floor === selectedFloor) { points.push([r.x_m, r.y_m]); }
    });
    if (!points.length) {
      state.responders.forEach(function (r) { if (r.x_m !== null) { points.push([r.x_m, r.y_m]); } });
    }
    if (!points.length) { points.push([0, 0]); }
    const xs = points.map(function (p) { return p[0]; });
    const ys = points.map(function (p) { return p[1]; });
    return [Math.min.apply(null, xs) - GRID_M, Math.min.apply(null, ys) - GRID_M,
      Math.max.apply(null, xs) + GRID_M, Math.max.apply(null, ys) + GRID_M];
  }

  function drawGrid(b) {
    layers.grid.clearLayers();
    const x0 = Math.floor(b[0] / GRID_M) * GRID_M;
    const y0 = Math.floor(b[1] / GRID_M) * GRID_M;
    const x1 = Math.ceil(b[2] / GRID_M) * GRID_M;
    const y1 = Math.ceil(b[3] / GRID_M) * GRID_M;
    const lines = [];
    for (let x = x0; x <= x1; x += GRID_M) { lines.push([ll(x, y0), ll(x, y1)]); }
    for (let y = y0; y <= y1; y += GRID_M) { lines.push([ll(x0, y), ll(x1, y)]); }
    L.polyline(lines, { color: '#bbb', weight: 1, interactive: false }).addTo(layers.grid);
    gridBounds = [x0, y0, x1, y1];
  }

  function drawPlan() {
    layers.plan.clearLayers();
    const plan = planOf(selectedFloor);
    if (plan && plan.outline.length) {
      L.polygon(plan.outline.map(function (p) { return ll(p[0], p[1]); }),
        { color: '#000', weight: 3, fill: true, fillColor: '#fff', fillOpacity: 0.6,
          interactive: false }).addTo(layers.plan);
    }
    if (!state.building) { return; }
    state.building.stairs.filter(function (s) { return s.floor === selectedFloor; })
      .forEach(function (s) {
        L.rectangle([ll(s.x_m - 0.6, s.y_m - 0.6), ll(s.x_m + 0.6, s.y_m + 0.6)],
          { color: '#0047b3', weight: 2, fillOpacity: 0.3, className: 'stairs' })
          .bindTooltip('Stairs ' + s.stairwell + (s.direction > 0 ? ' \u2191' : ' \u2193'),
            { permanent: true, direction: 'right', className: 'stairs-label' })
          .addTo(layers.plan);
      });
  }

  function fitFloor() {
    const b = floorBounds();
    drawGrid(b);
    drawPlan();
    map.fitBounds([ll(b[0], b[1]), ll(b[2], b[3])]);
    drawn.forEach(function (d) { d.floorDrawn = undefined; });
  }

  function responderColour(r) {
    if (r.alarms.some(function (a) { return a.severity === 'alarm'; })) { return '#c00000'; }
    if (r.alarms.length) { return '#e08a00'; }
    return '#0047b3';
  }

  function trackSegments(track) {
    const segments = [];
    let current = [];
    track.forEach(function (c) {
      if (c[3] === selectedFloor) { current.push(ll(c[0], c[1])); return; }
      if (current.length > 1) { segments.push(current); }
      current = [];
    });
    if (current.length > 1) { segments.push(current); }
    return segments;
  }

  function drawResponder(r) {
    let d = drawn.get(r.id);
    if (!d) {
      d = { group: L.layerGroup().addTo(layers.responders) };
      d.track = L.polyline([], { weight: 3, dashArray: '4 4', interactive: false }).addTo(d.group);
      d.circle = L.circle([0, 0], { radius: 1, weight: 1, fillOpacity: 0.12, interactive: false })
        .addTo(d.group);
      d.arrow = L.polyline([], { weight: 4, interactive: false }).addTo(d.group);
      d.dot = L.circleMarker([0, 0], { radius: 9, weight: 3, color: '#fff', fillOpacity: 1,
        className: 'responder' }).addTo(d.group);
      d.dot.on('click', function () { selectResponder(r.id, false); });
      // A label of fixed anchor: moving it never makes the browser measure it (a tooltip does).
      d.label = L.marker([0, 0], { interactive: false, keyboard: false }).addTo(d.group);
      drawn.set(r.id, d);
    } else if (!r.dirty && d.floorDrawn === selectedFloor) {
      return;
    }
    r.dirty = false;
    if (r.x_m === null) { d.group.remove(); return; }
    if (!layers.responders.hasLayer(d.group)) { d.group.addTo(layers.responders); }
    const here = r.floor === selectedFloor;
    const colour = here ? responderColour(r) : '#888';
    const opacity = here ? 1 : 0.35;
    const at = ll(r.x_m, r.y_m);
    d.dot.setLatLng(at);
    d.label.setLatLng(at);
    const look = colour + opacity;
    if (d.look !== look) {
      d.look = look;
      d.dot.setStyle({ fillColor: colour, opacity: opacity, fillOpacity: opacity });
      d.arrow.setStyle({ color: colour, opacity: opacity });
      d.track.setStyle({ color: colour, opacity: here ? 0.8 : 0.5 });
      d.circle.setStyle({ color: colour, opacity: 0.8 });
      const path = d.dot.getElement();
      path.classList.toggle('dimmed', !here);
      path.setAttribute('data-id', r.id);
    }
    const text = r.id.replace(/^\//, '') + (here ? '' : ' (' + floorText(r) + ')');
    const labelClass = 'responder-label' + (here ? '' : ' dimmed') +
      (here && colour === '#c00000' ? ' alarm' : '');
    if (d.labelText !== text + labelClass) {
      d.labelText = text + labelClass;
      d.label.setIcon(L.divIcon({ className: labelClass, html: escapeHtml(text),
        iconSize: null, iconAnchor: [-12, 30] }));
    }
    if (r.sigma_xy_m !== null && here) {
      d.circle.setLatLng(at).setRadius(Math.max(r.sigma_xy_m, 0.05));
      if (!d.group.hasLayer(d.circle)) { d.circle.addTo(d.group); }
    } else {
      d.circle.remove();
    }
    if (r.heading_deg !== null) {
      const h = r.heading_deg * Math.PI / 180;
      const tip = [r.x_m + ARROW_M * Math.cos(h), r.y_m + ARROW_M * Math.sin(h)];
      const side = function (s) {
        return ll(tip[0] - 0.6 * Math.cos(h + s), tip[1] - 0.6 * Math.sin(h + s));
      };
      d.arrow.setLatLngs([[at, ll(tip[0], tip[1])], [side(0.5), ll(tip[0], tip[1]), side(-0.5)]]);
    }
    if (r.trackChanged || d.floorDrawn !== selectedFloor) {
      d.track.setLatLngs(trackSegments(r.track));
      r.trackChanged = false;
    }
    if (here && d.floorDrawn !== selectedFloor) {
      d.group.eachLayer(function (layer) { if (layer.bringToFront) { layer.bringToFront(); } });
    }
    d.floorDrawn = selectedFloor;
  }

  function renderMap() {
    if (!map) { return; }
    const b = floorBounds();
    const anyone = Array.from(state.responders.values()).some(function (r) { return r.x_m !== null; });
    if (!gridBounds || (anyone && !fittedOnResponders)) {
      fittedOnResponders = anyone;
      fitFloor();
    }
    else if (b[0] < gridBounds[0] || b[1] < gridBounds[1] || b[2] > gridBounds[2] ||
             b[3] > gridBounds[3]) {
      drawGrid([Math.min(b[0], gridBounds[0]), Math.min(b[1], gridBounds[1]),
        Math.max(b[2], gridBounds[2]), Math.max(b[3], gridBounds[3])]);
    }
    state.responders.forEach(drawResponder);
  }

  // -- the side view of the floor stack -------------------------------------------------

  function renderSideView() {
    const W = 320;
    const H = 260;
    const floors = state.floors.map(function (f) {
      return { index: f.index, name: f.name || 'Floor ' + f.index, count: f.responders,
        possible: f.possible, alarms: f.alarms,
        z: f.elevation_m === null ? 3 * f.index : f.elevation_m };
    });
    const people = Array.from(state.responders.values()).filter(function (r) { return r.x_m !== null; });
    const zs = floors.map(function (f) { return f.z; }).concat(people.map(function (r) {
      return r.z_m === null ? 0 : r.z_m;
    }));
    const xs = people.map(function (r) { return r.x_m; });
    if (!zs.length) { zs.push(0); }
    if (!xs.length) { xs.push(0); }
    const z0 = Math.min.apply(null, zs) - 1;
    const z1 = Math.max.apply(null, zs) + 3;
    const x0 = Math.min.apply(null, xs) - 2;
    const x1 = Math.max.apply(null, xs) + 2;
    const px = function (x) { return 110 + (W - 120) * (x - x0) / Math.max(x1 - x0, 1); };
    const py = function (z) { return H - 10 - (H - 20) * (z - z0) / Math.max(z1 - z0, 1); };
    const parts = floors.map(function (f) {
      const sel = f.index === selectedFloor;
      return '<g class="floor-line" data-floor="' + f.index + '"><line x1="105" x2="' + (W - 5) +
        '" y1="' + py(f.z) + '" y2="' + py(f.z) + '" stroke="' + (sel ? '#0047b3' : '#444') +
        '" stroke-width="' + (sel ? 4 : 2) + '"/><text x="4" y="' + (py(f.z) + 4) + '"' +
        (f.alarms ? ' fill="#c00000" font-weight="bold"' : '') + '>' + escapeHtml(f.name) +
        ' (' + f.count + (f.possible ? ' +' + f.possible + '?' : '') + ')</text></g>';
    });
    people.forEach(function (r) {
      const z = r.z_m === null ? (floorInfo(r.floor) || { elevation_m: 0 }).elevation_m || 0 : r.z_m;
      parts.push('<circle class="side-responder" data-id="' + escapeHtml(r.id) + '" cx="' +
        px(r.x_m).toFixed(1) + '" cy="' + (py(z) - 6).toFixed(1) + '" r="5" fill="' +
        responderColour(r) + '"/>');
    });
    setHtml('side-view', parts.join(''));
  }

  // -- actions --------------------------------------------------------------------------

  function selectFloor(index) {
    selectedFloor = index;
    fitFloor();
    scheduleRender();
  }

  function selectResponder(id, pan) {
    const r = state.responders.get(id);
    if (!r) { return; }
    selectedResponder = id;
    if (r.floor !== null && r.floor !== selectedFloor) { selectFloor(r.floor); }
    if (pan && r.x_m !== null && map) { map.panTo(ll(r.x_m, r.y_m)); }
    scheduleRender();
  }

  function askToken(message) {
    return new Promise(function (resolve) {
      const dialog = $('token-dialog');
      $('token-error').hidden = !message;
      $('token-error').textContent = message || '';
      $('token-input').value = '';
      $('name-input').value = sessionStorage.getItem('commandCentreName') || '';
      const done = function (ok) {
        $('token-form').onsubmit = null;
        $('token-cancel').onclick = null;
        dialog.close();
        if (ok) {
          sessionStorage.setItem('commandCentreToken', $('token-input').value.trim());
          sessionStorage.setItem('commandCentreName', $('name-input').value.trim() || 'IC');
        }
        resolve(ok);
      };
      $('token-form').onsubmit = function (e) { e.preventDefault(); done(true); };
      $('token-cancel').onclick = function () { done(false); };
      dialog.showModal();
      $('token-input').focus();
    });
  }

  function write(path, body, message) {
    const token = sessionStorage.getItem('commandCentreToken');
    if (!token) {
      return askToken(message).then(function (ok) { return ok ? write(path, body) : null; });
    }
    body.by = sessionStorage.getItem('commandCentreName') || 'IC';
    return fetch(path, {
      method: 'POST', headers: { 'Content-Type': 'application/json', 'Authorization': 'Bearer ' + token },
      body: JSON.stringify(body),
    }).then(function (response) {
      if (response.status === 401) {
        sessionStorage.removeItem('commandCentreToken');
        return write(path, body, 'The token was refused; give the one the command printed.');
      }
      if (!response.ok) {
        return response.text().then(function (text) {
          let why = text;
          try { why = JSON.parse(text).error; } catch (e) { /* not JSON: show the text */ }
          alert(path + ' refused (HTTP ' + response.status + '): ' + why);
        });
      }
      return response.json();
    });
  }

  // -- the alarm tone (WebAudio; browsers start sound only after a click) ---------------

  function enableSound() {
    if (!audio) {
      const Context = window.AudioContext || window.webkitAudioContext;
      if (!Context) { $('sound').textContent = 'No sound in this browser'; return; }
      audio = new Context();
    }
    audio.resume().then(function () { $('sound').textContent = 'Alarm tone on'; });
  }

  function beep(frequency, start, duration) {
    const oscillator = audio.createOscillator();
    const gain = audio.createGain();
    oscillator.type = 'square';
    oscillator.frequency.value = frequency;
    gain.gain.setValueAtTime(0.25, audio.currentTime + start);
    gain.gain.setValueAtTime(0, audio.currentTime + start + duration);
    oscillator.connect(gain).connect(audio.destination);
    oscillator.start(audio.currentTime + start);
    oscillator.stop(audio.currentTime + start + duration);
  }

  function sound() {
    const open = activeAlarms().filter(function (p) { return !p.alarm.acknowledged; });
    if (!open.length || !audio || audio.state !== 'running') { return; }
    if (open.some(function (p) { return p.alarm.severity === 'alarm'; })) {
      beep(1000, 0, 0.25);
      beep(750, 0.3, 0.25);
    } else {
      beep(600, 0, 0.15);
    }
  }

  // -- start ----------------------------------------------------------------------------

  function start() {
    $('roster').querySelector('tbody').id = 'roster-body';
    $('log').querySelector('tbody').id = 'log-body';
    setUpMap();
    document.addEventListener('click', function (e) {
      const ack = e.target.closest('button.ack');
      if (ack) {
        e.stopPropagation();
        write('/api/ack', { alarm_id: ack.dataset.alarm });
        return;
      }
      const floor = e.target.closest('#floors button[data-floor]');
      if (floor) { selectFloor(Number(floor.dataset.floor)); return; }
      const row = e.target.closest('#roster tbody tr[data-id], #alarm-banner .banner-alarm');
      if (row) { selectResponder(row.dataset.id, true); }
    });
    document.addEventListener('click', function () { if (!audio) { enableSound(); } },
      { once: true });
    $('sound').addEventListener('click', enableSound);
    $('evacuate').addEventListener('click', function () {
      if (confirm('Order the evacuation of the building?')) { write('/api/evacuate', {}); }
    });
    $('roll-call').addEventListener('click', function () { write('/api/roll_call', {}); });
    setInterval(function () {
      $('clock').textContent = new Date().toISOString().substring(11, 19) + ' UTC';
      renderAges();
      sound();
    }, 1000);
    boot();
  }

  function boot() {
    loadState().then(connect).catch(function (error) {
      setConnection(false);
      $('connection').textContent = 'NO CONNECTION: ' + error.message;
      setTimeout(boot, 2000);
    });
  }

  document.addEventListener('DOMContentLoaded', start);
}());
