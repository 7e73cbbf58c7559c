// protolink web: draws the state that the server sends (server-sent events on /events, the same
// JSON as GET /api/state) on plain canvases. Every drawing function records the values it drew
// in window.efis, so a test can compare what is on the screen with what was sent.
'use strict';

const SKY = '#2f7fd6';
const GROUND = '#8a5a2b';
const PX_PER_DEG = 4; // pitch ladder scale on the attitude indicator
const efis = {
  frames: 0, roll_deg: null, pitch_deg: null, attitude_time_ms: null, heading_deg: null,
  heading_time_ms: null, airspeed_mps: null, tas_mps: null, gps_altitude_m: null, pressure_altitude_m: null,
  slip_ball: null, turn_coordinator: null, track_points: 0, wind_from_deg: null,
  wind_speed_mps: null, stale_types: [], live_types: [], connected: false, // live_types: scheduled types only (not TOAST, LOG)
  // What the tapes and the vertical speed indicator show, in the units shown (`--units`).
  units: null, speed_unit: null, altitude_unit: null, vertical_speed_unit: null,
  airspeed_shown: null, tas_shown: null, altitude_shown: null, vertical_speed_shown: null,
};
// The SI scales, until the server says otherwise (the same shape as `units` in the state).
const SI = {
  name: 'si', speed: { unit: 'm/s', per_si: 1 }, altitude: { unit: 'm', per_si: 1 },
  vertical_speed: { unit: 'm/s', per_si: 1 },
};
window.efis = efis;

const $ = (id) => document.getElementById(id);
const num = (v) => typeof v === 'number' && Number.isFinite(v);
const fmt = (v, digits) => (num(v) ? v.toFixed(digits) : '-');

function ctx2d(id) {
  const c = $(id);
  const g = c.getContext('2d');
  return { c, g, w: c.width, h: c.height };
}

function text(g, s, x, y, color, font, align) {
  g.fillStyle = color;
  g.font = font || '13px system-ui, sans-serif';
  g.textAlign = align || 'center';
  g.textBaseline = 'middle';
  g.fillText(s, x, y);
}

function invalidCross({ g, w, h }, label) {
  g.fillStyle = '#000';
  g.fillRect(0, 0, w, h);
  g.strokeStyle = '#ff5050';
  g.lineWidth = 2;
  g.beginPath();
  g.moveTo(10, 10); g.lineTo(w - 10, h - 10);
  g.moveTo(w - 10, 10); g.lineTo(10, h - 10);
  g.stroke();
  text(g, label, w / 2, h / 2, '#ff5050', 'bold 14px system-ui, sans-serif');
}

// An amber flag across the top of an instrument whose message type went stale: the needles
// show the last value, and the flag says it is old.
function staleFlag(id, label) {
  const { g, w } = ctx2d(id);
  const bw = Math.min(w - 8, 150);
  g.fillStyle = 'rgba(0,0,0,0.75)';
  g.fillRect(w / 2 - bw / 2, 30, bw, 22);
  text(g, `${label} STALE`, w / 2, 41, '#ffb020', 'bold 13px system-ui, sans-serif');
}

// ------------------------------------------------------------------ attitude

function drawAttitude(a) {
  const k = ctx2d('attitude');
  const { g, w, h } = k;
  if (!a || !num(a.roll_deg) || !num(a.pitch_deg)) {
    efis.roll_deg = null;
    efis.pitch_deg = null;
    invalidCross(k, 'NO ATTITUDE');
    return;
  }
  const roll = a.roll_deg;
  const pitch = Math.max(-90, Math.min(90, a.pitch_deg));
  const cx = w / 2;
  const cy = h / 2;
  const big = 2 * Math.hypot(w, h);
  g.save();
  g.translate(cx, cy);
  // A right bank turns the world anticlockwise on the screen; nose up moves it down.
  g.rotate(-roll * Math.PI / 180);
  g.translate(0, pitch * PX_PER_DEG);
  g.fillStyle = SKY;
  g.fillRect(-big, -big, 2 * big, big);
  g.fillStyle = GROUND;
  g.fillRect(-big, 0, 2 * big, big);
  // Pitch ladder: short lines only, so the sky/ground edge away from the centre stays clean.
  g.strokeStyle = '#fff';
  g.lineWidth = 1.5;
  for (let p = -30; p <= 30; p += 5) {
    if (p === 0) continue;
    const y = -p * PX_PER_DEG;
    const half = p % 10 === 0 ? 30 : 15;
    g.beginPath();
    g.moveTo(-half, y);
    g.lineTo(half, y);
    g.stroke();
    if (p % 10 === 0) {
      text(g, String(Math.abs(p)), -half - 12, y, '#fff', '11px system-ui, sans-serif');
    }
  }
  g.restore();
  // Bank scale: marks at 0, 10, 20, 30, 45, 60 degrees, and the pointer at the roll.
  const r = Math.min(w, h) / 2 - 16;
  g.strokeStyle = '#fff';
  g.lineWidth = 2;
  for (const m of [-60, -45, -30, -20, -10, 0, 10, 20, 30, 45, 60]) {
    const t = (m - 90) * Math.PI / 180;
    const len = m % 30 === 0 ? 12 : 7;
    g.beginPath();
    g.moveTo(cx + r * Math.cos(t), cy + r * Math.sin(t));
    g.lineTo(cx + (r + len) * Math.cos(t), cy + (r + len) * Math.sin(t));
    g.stroke();
  }
  g.save();
  g.translate(cx, cy);
  g.rotate(-roll * Math.PI / 180);
  g.fillStyle = '#ffd400';
  g.beginPath();
  g.moveTo(0, -r + 1);
  g.lineTo(-7, -r + 13);
  g.lineTo(7, -r + 13);
  g.closePath();
  g.fill();
  g.restore();
  // The aircraft symbol, fixed.
  g.strokeStyle = '#ffd400';
  g.lineWidth = 4;
  g.beginPath();
  g.moveTo(cx - 60, cy); g.lineTo(cx - 20, cy); g.lineTo(cx - 10, cy + 10);
  g.moveTo(cx + 60, cy); g.lineTo(cx + 20, cy); g.lineTo(cx + 10, cy + 10);
  g.stroke();
  g.fillStyle = '#ffd400';
  g.fillRect(cx - 3, cy - 3, 6, 6);
  text(g, `roll ${fmt(roll, 1)}°`, 8, h - 12, '#fff', '12px system-ui, sans-serif', 'left');
  if (!a.valid) text(g, 'ATTITUDE INVALID', cx, h - 14, '#ff5050', 'bold 13px system-ui, sans-serif');
  efis.roll_deg = roll;
  efis.pitch_deg = pitch;
  efis.attitude_time_ms = a.timestamp_ms;
  $('attitude-caption').textContent = `attitude: roll ${fmt(roll, 1)}°, pitch ${fmt(pitch, 1)}°`;
}

// ------------------------------------------------------------------ turn coordinator, slip ball

function drawTurn(a) {
  const k = ctx2d('turn');
  const { g, w, h } = k;
  if (!a || !num(a.turn_coordinator) || !num(a.slip_ball)) {
    efis.turn_coordinator = null;
    efis.slip_ball = null;
    invalidCross(k, 'NO TURN');
    return;
  }
  g.fillStyle = '#000';
  g.fillRect(0, 0, w, h);
  const cx = w / 2;
  const cy = h / 2 - 10;
  // One standard-rate turn (3 °/s) tilts the symbol to the L/R index marks at 20 degrees.
  const INDEX = 20;
  g.strokeStyle = '#fff';
  g.lineWidth = 3;
  for (const d of [-INDEX, 0, INDEX]) {
    const t = d * Math.PI / 180;
    for (const side of [-1, 1]) {
      g.beginPath();
      g.moveTo(cx + side * 95 * Math.cos(t), cy + side * 95 * Math.sin(t));
      g.lineTo(cx + side * 80 * Math.cos(t), cy + side * 80 * Math.sin(t));
      g.stroke();
    }
  }
  text(g, 'L', cx - 88, cy + 45, '#fff');
  text(g, 'R', cx + 88, cy + 45, '#fff');
  const tilt = Math.max(-2, Math.min(2, a.turn_coordinator)) * INDEX;
  g.save();
  g.translate(cx, cy);
  g.rotate(tilt * Math.PI / 180);
  g.strokeStyle = '#fff';
  g.fillStyle = '#fff';
  g.lineWidth = 5;
  g.beginPath();
  g.moveTo(-70, 0); g.lineTo(70, 0);
  g.moveTo(0, -18); g.lineTo(0, 0);
  g.stroke();
  g.beginPath();
  g.arc(0, 0, 9, 0, 2 * Math.PI);
  g.fill();
  g.restore();
  // The inclinometer: a ball in a curved tube; slip_ball is -1..1 of the tube's half width.
  const ty = h - 38;
  g.fillStyle = '#222';
  g.strokeStyle = '#888';
  g.lineWidth = 1;
  g.beginPath();
  g.roundRect(cx - 80, ty - 13, 160, 26, 13);
  g.fill();
  g.stroke();
  g.strokeStyle = '#fff';
  g.beginPath();
  g.moveTo(cx - 14, ty - 13); g.lineTo(cx - 14, ty + 13);
  g.moveTo(cx + 14, ty - 13); g.lineTo(cx + 14, ty + 13);
  g.stroke();
  const ball = Math.max(-1, Math.min(1, a.slip_ball));
  g.fillStyle = '#eee';
  g.beginPath();
  g.arc(cx + ball * 66, ty, 11, 0, 2 * Math.PI);
  g.fill();
  text(g, `turn ${fmt(a.turn_coordinator, 2)} std rate`, cx, h - 10, '#8b95a3', '12px system-ui, sans-serif');
  efis.turn_coordinator = a.turn_coordinator;
  efis.slip_ball = a.slip_ball;
}

// ------------------------------------------------------------------ heading

function drawHeading(hd) {
  const k = ctx2d('heading');
  const { g, w, h } = k;
  if (!hd || !num(hd.heading_deg)) {
    efis.heading_deg = null;
    invalidCross(k, 'NO HEADING');
    return;
  }
  const heading = ((hd.heading_deg % 360) + 360) % 360;
  const cx = w / 2;
  const cy = h / 2;
  const r = Math.min(w, h) / 2 - 8;
  g.fillStyle = '#000';
  g.fillRect(0, 0, w, h);
  g.save();
  g.translate(cx, cy);
  g.rotate(-heading * Math.PI / 180);
  g.strokeStyle = '#fff';
  for (let d = 0; d < 360; d += 5) {
    const len = d % 30 === 0 ? 14 : d % 10 === 0 ? 9 : 5;
    g.lineWidth = d % 10 === 0 ? 2 : 1;
    g.save();
    g.rotate(d * Math.PI / 180);
    g.beginPath();
    g.moveTo(0, -r);
    g.lineTo(0, -r + len);
    g.stroke();
    if (d % 30 === 0) {
      const label = { 0: 'N', 90: 'E', 180: 'S', 270: 'W' }[d] || String(d / 10);
      text(g, label, 0, -r + 26, d % 90 === 0 ? '#ffd400' : '#fff', 'bold 14px system-ui, sans-serif');
    }
    g.restore();
  }
  g.restore();
  // Lubber line and the aircraft.
  g.fillStyle = '#ffd400';
  g.beginPath();
  g.moveTo(cx, cy - r + 2); g.lineTo(cx - 7, cy - r - 6); g.lineTo(cx + 7, cy - r - 6);
  g.closePath();
  g.fill();
  g.strokeStyle = '#ffd400';
  g.lineWidth = 3;
  g.beginPath();
  g.moveTo(cx, cy - 22); g.lineTo(cx, cy + 22);
  g.moveTo(cx - 18, cy - 4); g.lineTo(cx + 18, cy - 4);
  g.moveTo(cx - 8, cy + 18); g.lineTo(cx + 8, cy + 18);
  g.stroke();
  g.fillStyle = 'rgba(0,0,0,0.7)';
  g.fillRect(cx - 30, cy + 30, 60, 22);
  text(g, `${fmt(heading, 0).padStart(3, '0')}°`, cx, cy + 41, hd.valid ? '#fff' : '#ff5050', 'bold 15px system-ui, sans-serif');
  efis.heading_deg = heading;
  efis.heading_time_ms = hd.timestamp_ms;
}

// ------------------------------------------------------------------ tapes

function drawTape(id, value, unitsPerTick, labelEvery, pxPerUnit, extra) {
  const k = ctx2d(id);
  const { g, w, h } = k;
  if (!num(value)) {
    invalidCross(k, 'NO DATA');
    return false;
  }
  g.fillStyle = '#1a1f26';
  g.fillRect(0, 0, w, h);
  const cy = h / 2;
  g.strokeStyle = '#fff';
  g.lineWidth = 1;
  const first = Math.floor((value - cy / pxPerUnit) / unitsPerTick) * unitsPerTick;
  for (let v = first; v <= value + cy / pxPerUnit; v += unitsPerTick) {
    const y = cy - (v - value) * pxPerUnit;
    const major = Math.round(v / unitsPerTick) % labelEvery === 0;
    g.beginPath();
    g.moveTo(w - (major ? 16 : 9), y);
    g.lineTo(w, y);
    g.stroke();
    if (major) text(g, String(Math.round(v)), w - 22, y, '#fff', '12px system-ui, sans-serif', 'right');
  }
  if (extra) extra(g, w, h, cy);
  g.fillStyle = '#000';
  g.strokeStyle = '#ffd400';
  g.lineWidth = 2;
  g.fillRect(2, cy - 13, w - 4, 26);
  g.strokeRect(2, cy - 13, w - 4, 26);
  text(g, value.toFixed(id === 'speed' ? 1 : 0), w / 2, cy, '#fff', 'bold 15px system-ui, sans-serif');
  return true;
}

// A value in the shown units, or null.
const scaled = (v, scale) => (num(v) ? v * scale.per_si : null);

function drawTapes(s, u) {
  const air = s.air;
  // The tape is the indicated airspeed; the true airspeed is the readout below it.
  const speed = air ? air.ias_mps : null;
  const tas = air ? air.tas_mps : null;
  const knots = u.speed.unit !== 'm/s';
  // m/s: a tick a unit, 6 px each; knots: a tick every 2 kt at the same pixels per m/s.
  const speedPx = 6 / u.speed.per_si;
  const speedShown = scaled(speed, u.speed);
  const tasShown = scaled(tas, u.speed);
  const speedDrawn = drawTape('speed', speedShown, knots ? 2 : 1, 5, speedPx, (g, w, h) => {
    if (num(tasShown)) text(g, `T ${tasShown.toFixed(0)}`, w / 2, h - 10, '#7fd4ff', '12px system-ui, sans-serif');
  });
  efis.airspeed_mps = speedDrawn ? speed : null;
  efis.airspeed_shown = speedDrawn ? speedShown : null;
  efis.tas_mps = speedDrawn && num(tas) ? tas : null;
  efis.tas_shown = speedDrawn && num(tasShown) ? tasShown : null;
  const gpsAlt = s.gps ? s.gps.altitude_m : null;
  const baroM = air ? air.pressure_altitude_m : null;
  const baro = scaled(baroM, u.altitude);
  const shown = num(gpsAlt) ? scaled(gpsAlt, u.altitude) : baro;
  // 1.5 px a metre in either unit; ticks every 10 m or every 20 ft.
  const altPx = 1.5 / u.altitude.per_si;
  const feet = u.altitude.unit !== 'm';
  const drawn = drawTape('altitude', shown, feet ? 20 : 10, 5, altPx, (g, w, h, cy) => {
    // The pressure altitude as a cyan mark and readout beside the GPS tape.
    if (num(baro) && num(shown)) {
      const y = Math.max(8, Math.min(h - 8, cy - (baro - shown) * altPx));
      g.fillStyle = '#7fd4ff';
      g.beginPath();
      g.moveTo(4, y); g.lineTo(14, y - 6); g.lineTo(14, y + 6);
      g.closePath();
      g.fill();
      text(g, `P ${baro.toFixed(0)}`, w / 2, h - 10, '#7fd4ff', '12px system-ui, sans-serif');
    }
  });
  efis.gps_altitude_m = drawn && num(gpsAlt) ? gpsAlt : null;
  efis.pressure_altitude_m = num(baroM) ? baroM : null;
  efis.altitude_shown = drawn ? shown : null;
  drawVsi(air ? air.vertical_speed_mps : null, u.vertical_speed);
}

// ------------------------------------------------------------------ vertical speed

// A vertical scale from -FULL to +FULL (6 m/s or 1200 ft/min), a needle from the zero mark,
// and the value in the box below.
function drawVsi(mps, scale) {
  const k = ctx2d('vsi');
  const { g, w, h } = k;
  const v = scaled(mps, scale);
  if (!num(v)) {
    efis.vertical_speed_shown = null;
    invalidCross(k, 'NO V/S');
    return;
  }
  const fpm = scale.unit === 'ft/min';
  const full = fpm ? 1200 : 6;
  const step = fpm ? 200 : 1;
  g.fillStyle = '#1a1f26';
  g.fillRect(0, 0, w, h);
  const cy = h / 2 - 14;
  const half = cy - 16;
  const yOf = (x) => cy - Math.max(-1, Math.min(1, x / full)) * half;
  g.strokeStyle = '#fff';
  g.lineWidth = 1;
  for (let m = -full; m <= full + 1e-9; m += step) {
    const y = yOf(m);
    const major = Math.round(m / step) % 2 === 0;
    g.beginPath();
    g.moveTo(6, y);
    g.lineTo(major ? 20 : 14, y);
    g.stroke();
    if (major) text(g, String(Math.abs(fpm ? m / 100 : m)), 34, y, '#fff', '11px system-ui, sans-serif');
  }
  g.strokeStyle = '#3ccf6e';
  g.lineWidth = 4;
  g.beginPath();
  g.moveTo(w - 8, cy);
  g.lineTo(22, yOf(v));
  g.stroke();
  g.fillStyle = '#000';
  g.strokeStyle = '#ffd400';
  g.lineWidth = 2;
  g.fillRect(2, h - 26, w - 4, 22);
  g.strokeRect(2, h - 26, w - 4, 22);
  text(g, `${v >= 0 ? '+' : ''}${v.toFixed(fpm ? 0 : 1)}`, w / 2, h - 15, '#fff', 'bold 14px system-ui, sans-serif');
  efis.vertical_speed_shown = v;
}

// ------------------------------------------------------------------ ground track and wind

function drawTrack(s, u) {
  const { g, w, h } = ctx2d('track');
  g.fillStyle = '#0b1a10';
  g.fillRect(0, 0, w, h);
  const pts = (s.track || []).filter((p) => Array.isArray(p) && num(p[0]) && num(p[1]));
  efis.track_points = pts.length;
  if (pts.length > 0) {
    const [lat0, lon0] = pts[pts.length - 1];
    const kx = 111320 * Math.cos(lat0 * Math.PI / 180);
    const ky = 110540;
    const xy = pts.map(([lat, lon]) => [(lon - lon0) * kx, (lat - lat0) * ky]);
    let minx = 0, maxx = 0, miny = 0, maxy = 0;
    for (const [x, y] of xy) {
      minx = Math.min(minx, x); maxx = Math.max(maxx, x);
      miny = Math.min(miny, y); maxy = Math.max(maxy, y);
    }
    const span = Math.max(200, maxx - minx, maxy - miny);
    const scale = (Math.min(w, h) - 40) / span;
    const ox = w / 2 - ((minx + maxx) / 2) * scale;
    const oy = h / 2 + ((miny + maxy) / 2) * scale;
    g.strokeStyle = '#3ccf6e';
    g.lineWidth = 2;
    g.beginPath();
    xy.forEach(([x, y], i) => (i ? g.lineTo(ox + x * scale, oy - y * scale) : g.moveTo(ox + x * scale, oy - y * scale)));
    g.stroke();
    g.fillStyle = '#fff';
    g.beginPath();
    g.arc(ox, oy, 4, 0, 2 * Math.PI);
    g.fill();
    // Scale bar: a round number of metres near a quarter of the width.
    const want = w / 4 / scale;
    const mag = Math.pow(10, Math.floor(Math.log10(want)));
    const bar = [1, 2, 5, 10].map((m) => m * mag).filter((m) => m <= want).pop() || mag;
    g.strokeStyle = '#fff';
    g.lineWidth = 2;
    g.beginPath();
    g.moveTo(10, h - 12); g.lineTo(10 + bar * scale, h - 12);
    g.stroke();
    text(g, bar >= 1000 ? `${bar / 1000} km` : `${bar} m`, 10 + bar * scale / 2, h - 24, '#fff', '11px system-ui, sans-serif');
  } else {
    text(g, 'no GPS fix yet', w / 2, h / 2, '#8b95a3');
  }
  text(g, 'N', w - 14, 12, '#ffd400', 'bold 12px system-ui, sans-serif');
  // Wind: the arrow points where the air goes (from direction + 180).
  const wind = s.wind;
  if (wind && num(wind.direction_deg) && num(wind.speed_mps)) {
    const cx = w - 36;
    const cy = h - 40;
    g.save();
    g.translate(cx, cy);
    g.rotate((wind.direction_deg + 180) * Math.PI / 180);
    g.strokeStyle = '#7fd4ff';
    g.fillStyle = '#7fd4ff';
    g.lineWidth = 3;
    g.beginPath();
    g.moveTo(0, 16); g.lineTo(0, -10);
    g.stroke();
    g.beginPath();
    g.moveTo(0, -18); g.lineTo(-7, -6); g.lineTo(7, -6);
    g.closePath();
    g.fill();
    g.restore();
    text(g, `${scaled(wind.speed_mps, u.speed).toFixed(1)} ${u.speed.unit} from ${wind.direction_deg.toFixed(0)}°`, cx - 40, h - 10, '#7fd4ff', '11px system-ui, sans-serif');
    efis.wind_from_deg = wind.direction_deg;
    efis.wind_speed_mps = wind.speed_mps;
  } else {
    efis.wind_from_deg = null;
    efis.wind_speed_mps = null;
  }
}

// ------------------------------------------------------------------ tables

function sparkline(canvas, intervals) {
  const g = canvas.getContext('2d');
  const w = canvas.width;
  const h = canvas.height;
  g.clearRect(0, 0, w, h);
  const v = (intervals || []).filter(num);
  if (v.length === 0) return;
  const mean = v.reduce((a, b) => a + b, 0) / v.length;
  const max = Math.max(mean * 2, ...v);
  const bw = w / v.length;
  v.forEach((x, i) => {
    const bh = Math.max(1, (x / max) * (h - 2));
    g.fillStyle = Math.abs(x - mean) > mean * 0.5 ? '#ffb020' : '#3ccf6e';
    g.fillRect(i * bw, h - bh, Math.max(1, bw - 1), bh);
  });
  // The mean as a line.
  g.fillStyle = '#fff';
  g.fillRect(0, h - 1 - (mean / max) * (h - 2), w, 1);
}

function cell(tr, value, cls) {
  const td = document.createElement('td');
  td.textContent = value;
  if (cls) td.className = cls;
  tr.appendChild(td);
  return td;
}

function drawTypes(types) {
  const body = $('types').tBodies[0];
  const rows = new Map([...body.rows].map((r) => [r.dataset.id, r]));
  const stale = [];
  const live = [];
  for (const t of types || []) {
    const key = String(t.id);
    let tr = rows.get(key);
    if (!tr) {
      tr = document.createElement('tr');
      tr.dataset.id = key;
      for (let i = 0; i < 7; i++) cell(tr, '');
      const c = document.createElement('canvas');
      c.width = 80;
      c.height = 18;
      tr.cells[5].appendChild(c);
      body.appendChild(tr);
    }
    rows.delete(key);
    const interval = num(t.interval_box_ms) ? t.interval_box_ms : t.interval_host_ms;
    tr.cells[0].textContent = t.name;
    tr.cells[1].textContent = t.id;
    tr.cells[2].textContent = t.count;
    tr.cells[3].textContent = t.stale || !t.periodic ? '-' : `${fmt(t.rate_hz, 1)} Hz`;
    tr.cells[4].textContent = t.periodic ? `${fmt(interval, 1)} ms` : '-';
    sparkline(tr.cells[5].firstChild, t.periodic ? t.intervals_ms : []);
    tr.cells[6].textContent = t.stale ? `STALE ${fmt(t.age_s, 1)} s` : t.periodic ? 'live' : `event ${fmt(t.age_s, 0)} s ago`;
    tr.cells[6].className = 'state';
    tr.className = t.stale ? 'stale' : '';
    if (t.stale) stale.push(t.name);
    else if (t.periodic) live.push(t.name);
  }
  for (const r of rows.values()) r.remove();
  efis.stale_types = stale;
  efis.live_types = live;
}

function drawErrors(e) {
  const body = $('errors').tBodies[0];
  body.textContent = '';
  const names = [
    ['checksum_errors', 'CRC errors'], ['frames_no_crc', 'frames without CRC'],
    ['overflows', 'overflows'], ['too_short', 'too short'], ['bad_escapes', 'bad escapes'],
    ['malformed', 'malformed'], ['truncated', 'truncated datagrams'],
    ['bytes_discarded', 'bytes discarded'],
  ];
  for (const [key, label] of names) {
    const tr = document.createElement('tr');
    const th = document.createElement('th');
    th.textContent = label;
    tr.appendChild(th);
    const v = e ? e[key] : null;
    cell(tr, num(v) ? String(v) : '-', num(v) && v > 0 && key !== 'frames_no_crc' ? 'bad' : '');
    body.appendChild(tr);
  }
}

function drawBox(s) {
  const i = s.info;
  $('model').textContent = i ? i.model : '-';
  $('firmware').textContent = i ? i.firmware : '-';
  $('mac').textContent = i ? i.mac : '-';
  $('identity').textContent = i ? `${i.model} ${i.firmware}` : '';
  $('toast').textContent = typeof s.toast === 'string' ? s.toast : '-';
  $('temp').textContent = num(s.temp_c) ? `${s.temp_c.toFixed(1)} °C` : '-';
  const p = s.gps;
  const u = s.units || SI;
  $('gps').textContent = p
    ? `${fmt(p.latitude_deg, 6)}, ${fmt(p.longitude_deg, 6)}  fix ${p.fix ? 'yes' : 'no'}  ${p.satellites} sats  ${fmt(scaled(p.ground_speed_mps, u.speed), 1)} ${u.speed.unit}`
    : '-';
  const v = s.server || {};
  $('server').textContent = `${v.clients} live clients, ${v.replaced} replaced, ${v.refused} refused, ${v.frames_sent} updates sent, ${v.frames_dropped} dropped for slow clients, ${v.bad_requests} bad requests, ${v.cross_site} cross-site refused, ${v.evicted} slow requests closed; ${s.bytes} bytes from ${s.source} in ${fmt(s.uptime_s, 0)} s`;
}

// ------------------------------------------------------------------ the loop

function draw(s) {
  $('source').textContent = s.source || '';
  const nd = $('nodata');
  nd.hidden = !s.no_data;
  nd.textContent = s.no_data ? `NO DATA: ${s.no_data}` : '';
  drawAttitude(s.attitude);
  drawTurn(s.attitude);
  drawHeading(s.heading);
  const u = s.units || SI;
  $('speed-unit').textContent = u.speed.unit;
  $('altitude-unit').textContent = u.altitude.unit;
  $('vsi-unit').textContent = u.vertical_speed.unit;
  efis.units = u.name;
  efis.speed_unit = u.speed.unit;
  efis.altitude_unit = u.altitude.unit;
  efis.vertical_speed_unit = u.vertical_speed.unit;
  drawTapes(s, u);
  drawTrack(s, u);
  drawTypes(s.types);
  const stale = new Set(efis.stale_types);
  if (s.attitude && stale.has('ATTITUDE')) {
    staleFlag('attitude', 'ATTITUDE');
    staleFlag('turn', 'ATTITUDE');
  }
  if (s.heading && stale.has('COMPASS')) staleFlag('heading', 'COMPASS');
  if (s.air && stale.has('PRESSURE')) staleFlag('speed', 'AIR');
  if (s.air && stale.has('PRESSURE')) staleFlag('vsi', 'AIR');
  if (s.gps && stale.has('GPS')) staleFlag('altitude', 'GPS');
  if (s.gps && stale.has('GPS')) staleFlag('track', 'GPS');
  drawErrors(s.errors);
  drawBox(s);
  efis.frames += 1;
}

// The live updates. A stream that breaks comes back by itself (the browser retries after the
// server's `retry`); one the server refuses (503: every place is taken) does not, so the page
// tries again itself, waiting 1, 2, 4 ... up to 30 s, and meanwhile polls GET /api/state once
// a second, so the instruments keep moving. efis.stream_retries counts the tries.
const RETRY_FIRST_MS = 1000;
const RETRY_MAX_MS = 30000;
const POLL_MS = 1000;
efis.stream_retries = 0;
efis.polled = 0;
let retryMs = RETRY_FIRST_MS;
let poller = null;

function show(s) {
  if (s && typeof s === 'object') draw(s);
}

function startPolling() {
  if (poller !== null) return;
  poller = setInterval(() => {
    fetch('/api/state', { cache: 'no-store' })
      .then((r) => (r.ok ? r.json() : null))
      .then((s) => {
        if (s && !efis.connected) {
          efis.polled += 1;
          show(s);
        }
      })
      .catch(() => {});
  }, POLL_MS);
}

function stopPolling() {
  if (poller === null) return;
  clearInterval(poller);
  poller = null;
}

function connect() {
  const link = $('link');
  const events = new EventSource('/events');
  events.onopen = () => {
    efis.connected = true;
    retryMs = RETRY_FIRST_MS;
    stopPolling();
    link.textContent = 'live';
    link.className = 'badge live';
  };
  events.onmessage = (ev) => {
    let s;
    try {
      s = JSON.parse(ev.data);
    } catch (e) {
      return;
    }
    show(s);
  };
  events.onerror = () => {
    efis.connected = false;
    link.className = 'badge lost';
    startPolling();
    if (events.readyState !== EventSource.CLOSED) {
      // The browser reconnects by itself.
      link.textContent = 'reconnecting';
      return;
    }
    // Refused (or the server gone): the browser has given up; try again later.
    link.textContent = `refused: retrying in ${Math.round(retryMs / 1000)} s (state polled)`;
    setTimeout(() => {
      efis.stream_retries += 1;
      connect();
    }, retryMs);
    retryMs = Math.min(retryMs * 2, RETRY_MAX_MS);
  };
}

draw({});
connect();
