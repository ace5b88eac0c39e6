"""A rotatable 3-D view of the deformed tip in one self-contained HTML file (inline WebGL, no network).

The deformed tip, cut along its bending plane as ``tip.png`` (triangles, decimated to at most
``max_triangles``) with per-vertex strain colours, a colour bar, mouse-drag
rotation, wheel zoom and double-click reset. Everything the page needs is in
the page: the geometry is inlined as base64 (vertex positions quantised to
16 bits over the bounding box, which is < 1e-4 of the tip's size), the viewer
is ~100 lines of plain WebGL 1. PyVista's ``export_html`` would need trame,
trame-vtk and trame-vuetify and inlines the whole vtk.js bundle (megabytes).

:func:`tip_view_fragment` gives a ``<figure>`` to put into a larger page (the
demo's index.html); :func:`write_tip_html` writes a stand-alone page
(``softcath fem ... --out DIR`` writes ``DIR/tip.html``).
"""

from __future__ import annotations

import base64
import html
import itertools
import json
import logging
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softcath.fem.export import cut_deformed, strain_clim, to_grid

__all__ = ["SurfaceView", "surface_of_grid", "tip_view_fragment", "write_tip_html", "write_view_html"]

log = logging.getLogger(__name__)

#: Largest number of surface triangles inlined (about 20 bytes of HTML each).
MAX_TRIANGLES = 16000
_ids = itertools.count(1)


@dataclass(frozen=True)
class SurfaceView:
    """A triangulated surface with one scalar per vertex, ready to inline.

    Attributes
    ----------
    points : ndarray, (n, 3)
        Vertex positions [mm] (deformed).
    triangles : ndarray, (m, 3)
        Vertex indices, n < 65536.
    values : ndarray, (n,)
        The colour scalar per vertex.
    clim : tuple of float
        Colour limits (values outside are clamped).
    label : str
        Colour bar title.
    """

    points: np.ndarray
    triangles: np.ndarray
    values: np.ndarray
    clim: tuple[float, float]
    label: str


def surface_of_grid(
    grid,
    *,
    scalars: str = "max_principal_strain",
    displacement: str = "displacement",
    label: str = "max principal strain",
    max_triangles: int = MAX_TRIANGLES,
    cut: bool = True,
) -> SurfaceView:
    """The deformed surface of a tet ``grid`` with ``scalars`` (cell data) averaged to the vertices.

    Parameters
    ----------
    grid : pyvista.UnstructuredGrid
        With point data ``displacement`` [mm] and cell data ``scalars``.
    max_triangles : int
        Quadric decimation down to this many triangles; the vertex values
        then come from the nearest vertex of the full surface.
    cut : bool
        Keep the half x <= 0 (cut along the bending plane, as ``tip.png``) so
        the lumen, filler and channel and the strain inside show.
    """
    from scipy.spatial import cKDTree

    clim = strain_clim(grid.cell_data[scalars])
    pts = cut_deformed(grid, displacement) if cut else grid.warp_by_vector(displacement, factor=1.0)
    pts = pts.cell_data_to_point_data()
    full = pts.extract_surface(algorithm="dataset_surface").triangulate()
    surf = full
    if full.n_cells > max_triangles:
        surf = full.decimate(1.0 - max_triangles / full.n_cells)
    tris = np.asarray(surf.faces).reshape(-1, 4)[:, 1:]
    values = np.asarray(full.point_data[scalars], float)
    if surf is not full:
        values = values[cKDTree(full.points).query(surf.points)[1]]
    log.debug("tip view: %d -> %d triangles", full.n_cells, len(tris))
    return SurfaceView(np.asarray(surf.points, float), tris, values, clim, label)


def _b64(a: np.ndarray, dtype: str) -> str:
    return base64.b64encode(np.ascontiguousarray(a, dtype=dtype).tobytes()).decode("ascii")


def _colours(values: np.ndarray, clim: tuple[float, float]) -> np.ndarray:
    from matplotlib import colormaps

    t = np.clip((values - clim[0]) / (clim[1] - clim[0]), 0.0, 1.0)
    return np.round(colormaps["viridis"](t)[:, :3] * 255).astype(np.uint8)


def _payload(view: SurfaceView) -> dict:
    if len(view.points) >= 65536:
        raise ValueError(f"{len(view.points)} vertices: the viewer's 16-bit indices take < 65536")
    lo, hi = view.points.min(axis=0), view.points.max(axis=0)
    span = np.where(hi > lo, hi - lo, 1.0)
    q = np.round((view.points - lo) / span * 65535)
    return {
        "lo": lo.tolist(),
        "span": span.tolist(),
        "pos": _b64(q, "<u2"),
        "idx": _b64(view.triangles, "<u2"),
        "rgb": _b64(_colours(view.values, view.clim), "u1"),
    }


_JS = """
(function(){
const D=__DATA__, root=document.getElementById(__ID__), cv=root.querySelector('canvas');
const gl=cv.getContext('webgl',{preserveDrawingBuffer:true,antialias:true});
if(!gl){root.querySelector('.tv-msg').textContent='This browser has no WebGL: the 3-D view is off.';return;}
const dec=s=>Uint8Array.from(atob(s),c=>c.charCodeAt(0)).buffer;
const q=new Uint16Array(dec(D.pos)), idx=new Uint16Array(dec(D.idx)), rgb=new Uint8Array(dec(D.rgb));
const n=q.length/3, P=new Float32Array(3*n), N=new Float32Array(3*n);
const c=[0,1,2].map(k=>D.lo[k]+D.span[k]/2), r=0.5*Math.hypot(...D.span);
for(let i=0;i<3*n;i++){const k=i%3;P[i]=(D.lo[k]+q[i]/65535*D.span[k]-c[k])/r;}
for(let t=0;t<idx.length;t+=3){  // area-weighted vertex normals
 const [a,b,d]=[idx[t]*3,idx[t+1]*3,idx[t+2]*3];
 const u=[0,1,2].map(k=>P[b+k]-P[a+k]), v=[0,1,2].map(k=>P[d+k]-P[a+k]);
 const f=[u[1]*v[2]-u[2]*v[1],u[2]*v[0]-u[0]*v[2],u[0]*v[1]-u[1]*v[0]];
 for(const o of [a,b,d]) for(let k=0;k<3;k++) N[o+k]+=f[k];
}
function sh(type,src){const s=gl.createShader(type);gl.shaderSource(s,src);gl.compileShader(s);return s;}
const pr=gl.createProgram();
gl.attachShader(pr,sh(gl.VERTEX_SHADER,'attribute vec3 p,nm,col;uniform mat3 R;uniform vec2 S;'+
 'varying vec3 vc,vn;void main(){vec3 q=R*p;vn=R*nm;vc=col;'+
 'gl_Position=vec4(q.x*S.x,q.y*S.y,-0.5*q.z,1.0);}'));
gl.attachShader(pr,sh(gl.FRAGMENT_SHADER,'precision mediump float;varying vec3 vc,vn;void main(){'+
 'vec3 n=normalize(vn);float l=0.35+0.65*abs(dot(n,normalize(vec3(0.3,0.4,1.0))));'+
 'gl_FragColor=vec4(vc*l,1.0);}'));
gl.linkProgram(pr);gl.useProgram(pr);
function buf(data,name,size,type,norm){const b=gl.createBuffer();gl.bindBuffer(gl.ARRAY_BUFFER,b);
 gl.bufferData(gl.ARRAY_BUFFER,data,gl.STATIC_DRAW);const l=gl.getAttribLocation(pr,name);
 gl.enableVertexAttribArray(l);gl.vertexAttribPointer(l,size,type,norm,0,0);}
buf(P,'p',3,gl.FLOAT,false);buf(N,'nm',3,gl.FLOAT,false);buf(rgb,'col',3,gl.UNSIGNED_BYTE,true);
const ib=gl.createBuffer();gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER,ib);
gl.bufferData(gl.ELEMENT_ARRAY_BUFFER,idx,gl.STATIC_DRAW);
const uR=gl.getUniformLocation(pr,'R'), uS=gl.getUniformLocation(pr,'S');
gl.enable(gl.DEPTH_TEST);
// start as tip.png (seen from +x, y up: screen x = -z), turned 25 degrees to show depth
// row-major 3x3
const mul=(A,B)=>{const C=[];for(let i=0;i<3;i++)for(let j=0;j<3;j++)
 C.push(A[3*i]*B[j]+A[3*i+1]*B[3+j]+A[3*i+2]*B[6+j]);return C;};
const rx=a=>[1,0,0,0,Math.cos(a),-Math.sin(a),0,Math.sin(a),Math.cos(a)];
const ry=a=>[Math.cos(a),0,Math.sin(a),0,1,0,-Math.sin(a),0,Math.cos(a)];
const R0=mul(ry(0.45),[0,0,-1,0,1,0,1,0,0]);
// initial zoom: the tip as seen first fills 90 % of the canvas
let mx=1e-9,my=1e-9;for(let i=0;i<n;i++){const x=P[3*i],y=P[3*i+1],z=P[3*i+2];
 mx=Math.max(mx,Math.abs(R0[0]*x+R0[1]*y+R0[2]*z));my=Math.max(my,Math.abs(R0[3]*x+R0[4]*y+R0[5]*z));}
const asp=()=>{const w=cv.clientWidth||1,h=cv.clientHeight||1;return [Math.min(1,h/w),Math.min(1,w/h)];};
const fit=()=>{const a=asp();return 0.9*Math.min(1/(mx*a[0]),1/(my*a[1]));};
let R=R0.slice(), zoom=fit();
function draw(){
 const w=cv.clientWidth,h=cv.clientHeight,dpr=window.devicePixelRatio||1;
 if(cv.width!==Math.round(w*dpr)||cv.height!==Math.round(h*dpr)){cv.width=Math.round(w*dpr);cv.height=Math.round(h*dpr);}
 gl.viewport(0,0,cv.width,cv.height);gl.clearColor(1,1,1,1);gl.clear(gl.COLOR_BUFFER_BIT|gl.DEPTH_BUFFER_BIT);
 const T=[R[0],R[3],R[6],R[1],R[4],R[7],R[2],R[5],R[8]];  // column-major for GLSL
 gl.uniformMatrix3fv(uR,false,T);const a=asp();gl.uniform2f(uS,zoom*a[0],zoom*a[1]);
 gl.drawElements(gl.TRIANGLES,idx.length,gl.UNSIGNED_SHORT,0);
}
let drag=null;
cv.addEventListener('pointerdown',e=>{drag=[e.clientX,e.clientY];cv.setPointerCapture(e.pointerId);});
cv.addEventListener('pointerup',()=>{drag=null;});
cv.addEventListener('pointermove',e=>{if(!drag)return;const dx=e.clientX-drag[0],dy=e.clientY-drag[1];
 drag=[e.clientX,e.clientY];R=mul(rx(dy*0.01),mul(ry(dx*0.01),R));draw();});
cv.addEventListener('wheel',e=>{e.preventDefault();zoom*=Math.exp(-e.deltaY*0.001);zoom=Math.min(50,Math.max(0.1,zoom));draw();},{passive:false});
cv.addEventListener('dblclick',()=>{R=R0.slice();zoom=fit();draw();});
window.addEventListener('resize',draw);
draw();
})();
"""


def _colour_bar(view: SurfaceView) -> str:
    from matplotlib import colormaps

    stops = ",".join(
        "#{:02x}{:02x}{:02x}".format(*(round(255 * c) for c in colormaps["viridis"](t)[:3]))
        for t in np.linspace(0, 1, 9)
    )
    lo, hi = view.clim
    lo = 0.0 if abs(lo) < 1e-3 * abs(hi) else lo  # round-off below zero, not a compression
    return (
        "<div style='display:flex;align-items:center;gap:.5em;font-size:.85em'>"
        f"<span>{lo:.3g}</span><span style='flex:0 0 14em;height:.9em;"
        f"background:linear-gradient(to right,{stops})'></span><span>{hi:.3g}</span>"
        f"<span>{html.escape(view.label)}</span></div>"
    )


def tip_view_fragment(view: SurfaceView, *, caption: str, height_px: int = 420) -> str:
    """A ``<figure class="tip-view">`` with the canvas, colour bar, caption and the inline viewer script."""
    eid = f"tipview{next(_ids)}"
    script = _JS.replace("__DATA__", json.dumps(_payload(view), separators=(",", ":"))).replace(
        "__ID__", json.dumps(eid)
    )
    return (
        f"<figure class='tip-view' id='{eid}' style='margin:1em 0'>"
        f"<canvas style='width:100%;height:{height_px}px;border:1px solid #ddd;touch-action:none;"
        "cursor:grab' aria-label='rotatable 3-D view of the deformed tip'></canvas>"
        f"<p class='tv-msg' style='margin:.2em 0'></p>{_colour_bar(view)}"
        f"<figcaption>{html.escape(caption)} Drag to rotate, wheel to zoom, double-click to "
        f"reset.</figcaption><script>{script}</script></figure>"
    )


def write_view_html(view: SurfaceView, path: str | Path, *, title: str, caption: str = "") -> Path:
    """Write a stand-alone page with one 3-D view (no external resources)."""
    path = Path(path)
    doc = (
        "<!doctype html><html lang='en'><head><meta charset='utf-8'>"
        f"<title>{html.escape(title)}</title>"
        "<style>body{font-family:sans-serif;max-width:70em;margin:1em auto;padding:0 1em}</style>"
        "</head><body>"
        f"<h1>{html.escape(title)}</h1>"
        f"{tip_view_fragment(view, caption=caption, height_px=560)}</body></html>\n"
    )
    path.write_text(doc, encoding="utf-8")
    return path


def write_tip_html(solution, load: str, pressure_MPa: float, path: str | Path, **kwargs) -> Path:
    """The linear FEM's deformed tip at ``pressure_MPa`` (true scale) as a stand-alone 3-D page.

    ``kwargs`` go to :func:`surface_of_grid` (e.g. ``max_triangles``).
    """
    view = surface_of_grid(to_grid(solution, load, pressure_MPa), **kwargs)
    return write_view_html(
        view,
        path,
        title=f"Deformed tip: {load} load, p = {pressure_MPa:g} MPa",
        caption=(
            "Linear FEM, true scale, cut along the bending plane, coloured by the largest principal strain."
        ),
    )
