"""A self-contained HTML animation of a run: the robot moving in 3D, offline.

One file, no network: the frame data is embedded as JSON and drawn by a small inline
canvas-2D renderer (no WebGL, no libraries). Per frame the link frames ``T_0..T_n`` come
from :class:`~irlc.runtime.model.kinematics.Kinematics` at ``q(t)``; the page draws

* the kinematic skeleton through the joint origins ``o_0 … o_n`` and the TCP,
* the robot's collision capsules / spheres (link geometry) as thick round-capped lines
  or discs, their width scaled by the perspective ``f / depth``,
* the obstacles of the run, the whole TCP path and a floor grid.

Projection: orbit camera around the scene centre ``c`` with yaw ψ, pitch φ, distance
``r``; a world point ``p`` maps to camera coordinates ``(u, v, w) = Rᵀ(p − e)`` with the
eye ``e = c + r·(cos φ cos ψ, cos φ sin ψ, sin φ)``, and to the screen
``(W/2 + f·u/w, H/2 − f·v/w)``. Primitives are painted far to near (painter's algorithm).

The embedded data names its units (``units``: lengths mm, joint values deg | mm, times
s) and the joints by the naming rule (``joint_labels``: ``a4 (panda_joint4)``).
Numbers are millimetres rounded to integers; at most :data:`MAX_FRAMES` frames are kept
(uniform decimation, the last sample always included).
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
from irlc.files import atomic_write_text
from irlc.run_data import RunData, run_data
from irlc.runtime import units
from irlc.runtime.model.kinematics import Kinematics

MAX_FRAMES = 2000
UNITS = {"length": "mm", "angle": "deg", "time": "s"}
STATUS_ID = "irlc-status"  # the page writes "ok" or "error: …" here (used by tests)


def frame_indices(k: int, max_frames: int = MAX_FRAMES) -> np.ndarray:
    """Indices of the kept samples: every ``ceil(k / max_frames)``-th and the last one."""
    step = max(1, math.ceil(k / max_frames))
    idx = np.arange(0, k, step)
    if idx[-1] != k - 1:
        idx = np.append(idx[:-1] if len(idx) >= max_frames else idx, k - 1)
    return idx


def _mm(points: np.ndarray) -> list:
    return np.rint(np.asarray(points) / units.MM).astype(int).tolist()


def _geometry_points(model, frames: np.ndarray) -> list[np.ndarray]:
    """World points of the link geometry: capsule ends ``a, b``; sphere centres."""
    pts = []
    for g in model.geometry:
        t = frames[g.link]
        for local in (g.a, g.b) if hasattr(g, "a") else (g.center,):
            pts.append(t[:3, :3] @ np.asarray(local, dtype=float) + t[:3, 3])
    return pts


def _shapes(model) -> list[dict]:
    """Static description of the link geometry; point indices follow the skeleton."""
    shapes, k = [], model.n + 2  # skeleton: o_0 … o_n and the TCP
    for g in model.geometry:
        if hasattr(g, "a"):
            shapes.append({"type": "capsule", "i": [k, k + 1], "r": _mm(g.radius), "link": g.link})
            k += 2
        else:
            shapes.append({"type": "sphere", "i": [k], "r": _mm(g.radius), "link": g.link})
            k += 1
    return shapes


def _frame_points(kin: Kinematics, q: np.ndarray) -> np.ndarray:
    frames = kin.link_frames(q)
    skeleton = [frames[i, :3, 3] for i in range(kin.n + 1)]
    skeleton.append(kin.tcp_from_frames(frames)[:3, 3])
    return np.array(skeleton + _geometry_points(kin.model, frames))


def _obstacle(o: Any) -> dict | None:
    kind = getattr(o, "kind", None)
    name = str(getattr(o, "name", kind))
    if kind == "point":
        return {"type": "point", "name": name, "c": _mm(o.position)}
    if kind == "sphere":
        return {"type": "sphere", "name": name, "c": _mm(o.center), "r": _mm(o.radius)}
    if kind == "capsule":
        return {"type": "capsule", "name": name, "a": _mm(o.a), "b": _mm(o.b), "r": _mm(o.radius)}
    if kind == "box":
        half = 0.5 * np.asarray(o.size, dtype=float)
        signs = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)])
        corners = np.asarray(o.center) + (signs * half) @ np.asarray(o.rotation).T
        return {"type": "box", "name": name, "corners": _mm(corners)}
    if kind == "plane":
        return {
            "type": "plane",
            "name": name,
            "p": _mm(o.point),
            "n": np.round(o.normal, 4).tolist(),
        }
    return None


def animation_data(run: Any) -> dict:
    """The JSON the page embeds (see the module docstring for the geometry); a cell's
    (several robots) is :func:`cell_animation_data`."""
    if getattr(run, "is_cell", False):
        return cell_animation_data(run)
    d: RunData = run_data(run)
    if d.model is None:
        raise ValueError("the animation needs the robot model (link frames); the run has none")
    idx = frame_indices(d.k)
    lines = d.lines[idx].tolist() if d.lines is not None else [0] * len(idx)
    return {
        "program": d.report.get("program") or d.label,
        "robot": d.report.get("robot") or d.model.name,
        "status": d.report.get("status", "ok"),
        "units": dict(UNITS),
        **_robot_frames(d, d.model, idx),
        "obstacles": [s for s in (_obstacle(o) for o in d.obstacles) if s is not None],
        "t": [round(float(d.times[i]), 3) for i in idx],
        "line": [int(v) for v in lines],
    }


def _robot_frames(d: RunData, model, idx: np.ndarray) -> dict:
    """One robot's part of the page's data at the kept samples ``idx``: its joints, link
    geometry, the points of every frame (skeleton, TCP, geometry) and the TCP path."""
    kin = Kinematics(model)
    frames = [_frame_points(kin, d.q[i]) for i in idx]
    if d.tcp is not None:  # the run's TCP: with the program's tool (R_TOOL), not the file's
        for pts, i in zip(frames, idx, strict=True):
            pts[kin.n + 1] = d.tcp[i]
    points = [_mm(pts) for pts in frames]
    tcp = np.array([pts[kin.n + 1] for pts in frames])
    return {
        "n": d.n,
        "joint_names": list(d.joint_names),
        "robot_joint_names": list(d.robot_joint_names),
        "joint_labels": [d.joint_label(j) for j in range(d.n)],
        "shapes": _shapes(model),
        "joints": [[round(float(v), 2) for v in d.program_units(d.q[i])] for i in idx],
        "points": points,
        "path": _mm(tcp),
    }


def cell_animation_data(run: Any) -> dict:
    """A cell's page data: every robot in one scene, placed by its ``AT`` (its model's
    base), ``robots`` holding each robot's part as :func:`animation_data` has it for one
    robot (with ``name``, ``robot``, ``at``), and ``clearance`` per frame: the least
    distance between watched links (:class:`~irlc.runtime.model.clearance.PartSet`, as
    the run watches them) from the frame's joints, its two closest points (mm) and pair."""
    from irlc.robot_runs import robot_runs
    from irlc.runtime.model.clearance import PartSet, RobotParts

    robots = robot_runs(run)
    first = robots[0].data
    idx = frame_indices(first.k)
    parts = PartSet([RobotParts(r.name, Kinematics(r.model)) for r in robots])
    kins = [p.kin for p in parts.robots]
    clearance: dict[str, list] = {"mm": [], "a": [], "b": [], "pair": []}
    for i in idx:
        ends = parts.world([k.link_frames(r.data.q[i]) for k, r in zip(kins, robots, strict=True)])
        near = parts.closest(*ends)
        if near is None:
            continue
        clearance["mm"].append(round(near.distance / units.MM, 1))
        clearance["a"].append(_mm(near.point_a))
        clearance["b"].append(_mm(near.point_b))
        clearance["pair"].append(
            f"{parts.label(near.robot_a, near.link_a)} – {parts.label(near.robot_b, near.link_b)}"
        )
    lines = first.lines[idx].tolist() if first.lines is not None else [0] * len(idx)
    required = (run.report.get("clearance") or {}).get("required_mm") or 0.0
    return {
        "program": run.report.get("program") or first.label,
        "robot": run.report.get("robot", ""),
        "status": run.report.get("status", "ok"),
        "units": dict(UNITS),
        "robots": [
            {
                "name": r.name,
                "robot": r.data.report.get("robot") or r.model.name,
                "at": list(r.data.report.get("at") or [0.0] * 6),
                **_robot_frames(r.data, r.model, idx),
            }
            for r in robots
        ],
        "obstacles": [s for s in (_obstacle(o) for o in first.obstacles) if s is not None],
        "t": [round(float(first.times[i]), 3) for i in idx],
        "line": [int(v) for v in lines],
        "clearance": clearance if clearance["mm"] else None,
        "required_mm": required,
    }


def write_animation(run: Any, path: str | Path) -> Path:
    """Write the self-contained HTML animation of ``run`` to ``path`` (atomic)."""
    data = animation_data(run)
    payload = json.dumps(data, separators=(",", ":")).replace("</", "<\\/")
    html = _TEMPLATE.replace("__TITLE__", _escape(f"{data['program']} on {data['robot']}"))
    html = html.replace("__STATUS_ID__", STATUS_ID).replace("__DATA__", payload)
    path = Path(path)
    atomic_write_text(path, html)
    return path


def _escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")


_TEMPLATE = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8">
<title>irlc: __TITLE__</title>
<style>
 body{margin:0;font:13px system-ui,sans-serif;background:#f4f5f7;color:#222;overflow:hidden}
 #bar{position:fixed;left:0;right:0;bottom:0;display:flex;gap:10px;align-items:center;
      padding:6px 10px;background:#fff;border-top:1px solid #ccc}
 #slider{flex:1} #info{font-variant-numeric:tabular-nums;min-width:210px}
 #title{position:fixed;left:10px;top:8px;font-weight:600}
 #joints{position:fixed;right:10px;top:8px;font:11px monospace;white-space:pre;text-align:right;
         color:#444}
 #hint{position:fixed;left:10px;top:26px;color:#777;font-size:11px}
 #__STATUS_ID__{display:none} button{min-width:64px}
</style></head><body>
<canvas id="view"></canvas>
<div id="title">__TITLE__</div>
<div id="hint">drag: orbit · wheel: zoom · space: play/pause</div>
<pre id="joints"></pre>
<div id="bar"><button id="play">Play</button>
 <select id="speed"><option value="0.25">0.25×</option><option value="0.5">0.5×</option>
  <option value="1" selected>1×</option><option value="2">2×</option>
  <option value="5">5×</option></select>
 <input id="slider" type="range" min="0" value="0"><span id="info"></span></div>
<div id="__STATUS_ID__">loading</div>
<script id="irlc-data" type="application/json">__DATA__</script>
<script>
"use strict";
const statusEl = document.getElementById("__STATUS_ID__");
window.addEventListener("error", e => { statusEl.textContent = "error: " + e.message; });
try {
const D = JSON.parse(document.getElementById("irlc-data").textContent);
const cv = document.getElementById("view"), g = cv.getContext("2d");
const slider = document.getElementById("slider"), info = document.getElementById("info");
const playBtn = document.getElementById("play"), speedSel = document.getElementById("speed");
const jointsEl = document.getElementById("joints");
const N = D.t.length; slider.max = N - 1;
const R = D.robots || [D];  // a cell: every robot, placed in the cell frame
const COLORS = ["#e07a1f","#2f6db5","#3a9a4a","#b53f3f","#7a4fb0","#1f9aa8","#b0892f","#c2548f"];

// scene bounds over all frames, the path and the obstacles
let lo = [1e18,1e18,1e18], hi = [-1e18,-1e18,-1e18];
function grow(p){ for (let k=0;k<3;k++){ lo[k]=Math.min(lo[k],p[k]); hi[k]=Math.max(hi[k],p[k]); } }
for (const r of R){ for (const f of r.points) for (const p of f) grow(p); r.path.forEach(grow); }
for (const o of D.obstacles){
  if (o.c) grow(o.c);
  if (o.a){ grow(o.a); grow(o.b); }
  if (o.corners) o.corners.forEach(grow);
}
const centre = [0,1,2].map(k => (lo[k]+hi[k])/2);
const size = Math.max(hi[0]-lo[0], hi[1]-lo[1], hi[2]-lo[2], 1);
const floorZ = Math.min(lo[2], 0);
const cam = {yaw: -0.9, pitch: 0.45, dist: 1.7*size};

let W = 0, H = 0, f = 1;
function resize(){
  W = cv.width = innerWidth; H = cv.height = innerHeight - 40; f = 0.9*Math.min(W,H); draw();
}

// orbit camera: eye on a sphere around the centre, z up
function basis(){
  const cy=Math.cos(cam.yaw), sy=Math.sin(cam.yaw), cp=Math.cos(cam.pitch), sp=Math.sin(cam.pitch);
  const back=[cp*cy, cp*sy, sp];                    // from centre to eye
  const right=[-sy, cy, 0];
  const up=[-sp*cy, -sp*sy, cp];
  const eye=[0,1,2].map(k=>centre[k]+cam.dist*back[k]);
  return {eye, right, up, back};
}
let B = null;
function project(p){
  const d=[p[0]-B.eye[0], p[1]-B.eye[1], p[2]-B.eye[2]];
  const u=d[0]*B.right[0]+d[1]*B.right[1]+d[2]*B.right[2];
  const v=d[0]*B.up[0]+d[1]*B.up[1]+d[2]*B.up[2];
  const w=-(d[0]*B.back[0]+d[1]*B.back[1]+d[2]*B.back[2]);
  const z=Math.max(w, 1e-3*size);
  return [W/2 + f*u/z, H/2 - f*v/z, z];
}
// primitives: {z, draw()}; painted far to near
function seg(a,b,widthMm,color,alpha){
  const A=project(a), Bp=project(b), z=(A[2]+Bp[2])/2;
  return {z, draw(){ g.globalAlpha=alpha; g.strokeStyle=color; g.lineCap="round";
    g.lineWidth=Math.max(1.5, 2*widthMm*f/z);
    g.beginPath(); g.moveTo(A[0],A[1]); g.lineTo(Bp[0],Bp[1]); g.stroke(); }};
}
function disc(c,rMm,color,alpha,minPx){
  const P=project(c);
  return {z:P[2], draw(){ g.globalAlpha=alpha; g.fillStyle=color; g.beginPath();
    g.arc(P[0],P[1],Math.max(minPx||2, rMm*f/P[2]),0,2*Math.PI); g.fill(); }};
}
function label(p,text){
  const P=project(p);
  return {z:P[2]-1e9, draw(){ g.globalAlpha=1; g.fillStyle="#8e2a20"; g.font="12px sans-serif";
    g.fillText(text,P[0]+8,P[1]-8); }};
}
function anchor(o){
  if (o.c) return o.c;
  if (o.a) return [0,1,2].map(k=>(o.a[k]+o.b[k])/2);
  if (o.corners) return [0,1,2].map(k=>o.corners.reduce((s,p)=>s+p[k],0)/8);
  return o.p;
}
function poly(pts,color,alpha){
  const P=pts.map(project), z=P.reduce((s,p)=>s+p[2],0)/P.length;
  return {z, draw(){ g.globalAlpha=alpha; g.fillStyle=color; g.strokeStyle="#555"; g.lineWidth=0.7;
    g.beginPath(); P.forEach((p,i)=> i? g.lineTo(p[0],p[1]) : g.moveTo(p[0],p[1]));
    g.closePath(); g.fill(); g.stroke(); }};
}
const BOX_FACES=[[0,1,3,2],[4,5,7,6],[0,1,5,4],[2,3,7,6],[0,2,6,4],[1,3,7,5]];
function obstacleItems(){
  const items=[];
  for (const o of D.obstacles){
    if (o.type==="point") items.push(disc(o.c,0,"#c0392b",0.9,6));
    if (o.type==="sphere") items.push(disc(o.c,o.r,"#c0392b",0.35));
    else if (o.type==="capsule") items.push(seg(o.a,o.b,o.r,"#c0392b",0.35));
    else if (o.type==="box")
      for (const fc of BOX_FACES) items.push(poly(fc.map(i=>o.corners[i]),"#c0392b",0.18));
    else if (o.type==="plane"){
      const n=o.n, t1=Math.abs(n[2])<0.9?[ -n[1], n[0], 0]:[1,0,0];
      const l1=Math.hypot(...t1); const a=t1.map(v=>v/l1);
      const b=[n[1]*a[2]-n[2]*a[1], n[2]*a[0]-n[0]*a[2], n[0]*a[1]-n[1]*a[0]]; const h=0.6*size;
      const c=[[-1,-1],[1,-1],[1,1],[-1,1]].map(([s,t])=>[0,1,2].map(k=>o.p[k]+h*(s*a[k]+t*b[k])));
      items.push(poly(c,"#c0392b",0.12));
    }
  }
  for (const o of D.obstacles) items.push(label(anchor(o),o.name));
  return items;
}
function floorGrid(){
  const step=Math.pow(10, Math.floor(Math.log10(size/2))), items=[], m=0.15*size;
  const x0=Math.floor((lo[0]-m)/step)*step, y0=Math.floor((lo[1]-m)/step)*step;
  const x1=hi[0]+m, y1=hi[1]+m;
  for (let x=x0; x<=x1; x+=step) items.push(seg([x,y0,floorZ],[x,y1,floorZ],0,"#bbb",1));
  for (let y=y0; y<=y1; y+=step) items.push(seg([x0,y,floorZ],[x1,y,floorZ],0,"#bbb",1));
  return items;
}
let frame = 0;
function draw(){
  if (!W) return;
  B = basis();
  g.globalAlpha=1; g.fillStyle="#f4f5f7"; g.fillRect(0,0,W,H);
  const items = [];
  for (const s of floorGrid()) s.draw();
  items.push(...obstacleItems());
  R.forEach((r, k) => {
    const P = r.points[frame];
    for (let i=1;i<r.path.length;i++) items.push(seg(r.path[i-1],r.path[i],0,"#888",0.8));
    for (const s of r.shapes){
      const col=COLORS[(s.link-1+3*k+COLORS.length)%COLORS.length];
      if (s.type==="capsule") items.push(seg(P[s.i[0]],P[s.i[1]],s.r,col,0.8));
      else items.push(disc(P[s.i[0]],s.r,col,0.8));
    }
    for (let i=1;i<=r.n+1;i++) items.push(seg(P[i-1],P[i],0,"#222",1));
    for (let i=0;i<=r.n;i++) items.push(disc(P[i],0.012*size,"#222",1));
    items.push(disc(P[r.n+1],0.02*size,"#e0b000",1));
    if (r.name) items.push(label(P[0], r.name));
  });
  const C = D.clearance;
  let gap = "";
  if (C){  // the closest watched pair of links: a red line between its closest points
    const a=C.a[frame], b=C.b[frame], low = D.required_mm>0 && C.mm[frame] < D.required_mm;
    items.push(seg(a,b,0,low?"#d00000":"#c0392b",1), disc(a,0,"#c0392b",1,3),
               disc(b,0,"#c0392b",1,3), label([0,1,2].map(k=>(a[k]+b[k])/2), C.mm[frame]+" mm"));
    gap = "   clearance " + C.mm[frame].toFixed(1) + " mm (" + C.pair[frame] + ")";
  }
  items.sort((a,b)=>b.z-a.z);
  for (const it of items) it.draw();
  g.globalAlpha=1;
  info.textContent = "t = " + D.t[frame].toFixed(2) + " s   line " + D.line[frame]
    + "   frame " + (frame+1) + "/" + N + gap;
  jointsEl.textContent = R.map(r => r.joint_labels
    .map((nm,i) => (r.name ? r.name + " " : "") + nm + " " + r.joints[frame][i].toFixed(2))
    .join("\\n")).join("\\n\\n");
  slider.value = frame;
}
// playback in simulated time
let playing=false, simT=0, last=null;
function seek(t){
  let a=0, b=N-1;
  while (a<b){ const m=(a+b+1)>>1; if (D.t[m]<=t) a=m; else b=m-1; }
  return a;
}
function tick(now){
  if (!playing) return;
  if (last!==null) simT += (now-last)/1000*parseFloat(speedSel.value);
  last=now;
  if (simT>=D.t[N-1]) { simT=D.t[N-1]; playing=false; playBtn.textContent="Play"; }
  frame=seek(simT); draw();
  if (playing) requestAnimationFrame(tick);
}
function toggle(){
  playing=!playing; playBtn.textContent=playing?"Pause":"Play"; last=null;
  if (playing){ if (frame>=N-1) simT=D.t[0]; else simT=D.t[frame]; requestAnimationFrame(tick); }
}
playBtn.onclick=toggle;
addEventListener("keydown", e=>{ if (e.code==="Space"){ e.preventDefault(); toggle(); } });
slider.oninput=()=>{ frame=+slider.value; simT=D.t[frame]; draw(); };
let drag=null;
cv.onmousedown=e=>{ drag=[e.clientX,e.clientY]; };
addEventListener("mouseup",()=>{ drag=null; });
addEventListener("mousemove",e=>{ if(!drag) return;
  cam.yaw -= (e.clientX-drag[0])*0.008;
  cam.pitch = Math.max(-1.5, Math.min(1.5, cam.pitch+(e.clientY-drag[1])*0.008));
  drag=[e.clientX,e.clientY]; draw(); });
cv.addEventListener("wheel", e=>{ e.preventDefault(); cam.dist*=Math.exp(e.deltaY*0.001); draw(); },
                    {passive:false});
addEventListener("resize", resize);
const start = /t=([0-9.]+)/.exec(location.hash);  // e.g. anim.html#t=3.5 opens at 3.5 s
if (start) { frame = seek(parseFloat(start[1])); simT = D.t[frame]; }
resize();
statusEl.textContent = "ok";
} catch (e) { statusEl.textContent = "error: " + e.message; }
</script></body></html>
"""
