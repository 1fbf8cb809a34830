"""The GPU copy of a Scene: one vertex/index buffer per distinct mesh, one texture per material
texture, and the per-node uniforms. Built once, drawn by any program with the standard inputs
``in_position``, ``in_normal``, ``in_uv`` (those a program lacks are skipped)."""

from __future__ import annotations

from dataclasses import dataclass

import moderngl
import numpy as np

from ..core.context import Context
from ..core.gl import set_uniform
from ..scene.camera import View
from ..scene.scene import Node, Scene
from ..scene.transforms import transform_points
from .texture_footprint import ANISOTROPY_THRESHOLD, footprint_anisotropy

__all__ = ["GpuScene", "GpuMesh", "MAX_ANISOTROPY"]

MAX_ANISOTROPY = 8.0
# meshes with more triangles keep anisotropic filtering without measuring their footprint (a
# per-frame NumPy pass over them would cost more than the filter saves)
FOOTPRINT_MAX_FACES = 4096


@dataclass
class GpuMesh:
    vbo: moderngl.Buffer
    ibo: moderngl.Buffer
    triangles: int
    has_uvs: bool


class GpuScene:
    """Buffers and textures of one scene on one context. ``draw(program, set_node)`` draws every
    visible node, calling ``set_node(index, node)`` first to set per-node uniforms."""

    def __init__(self, ctx: Context, scene: Scene):
        self.ctx = ctx
        self.scene = scene
        self._meshes: dict[int, GpuMesh] = {}
        self._textures: dict[int, moderngl.Texture] = {}
        self._vaos: dict[tuple[int, int], moderngl.VertexArray] = {}
        self._corner_key: tuple[int, ...] | None = None  # bounding-box corners, see _corners
        self._corner_cache = np.zeros((0, 8, 4))
        for node in scene.nodes:
            self._mesh(node)
            if node.material.texture is not None:
                self.texture(node)

    def _mesh(self, node: Node) -> GpuMesh:
        key = id(node.mesh)
        gm = self._meshes.get(key)
        if gm is None:
            m = node.mesh
            uvs = m.uvs if m.uvs is not None else np.zeros((len(m.vertices), 2), np.float32)
            data = np.hstack([m.vertices, m.normals, uvs]).astype(np.float32)
            self.ctx.make_current()
            gm = GpuMesh(
                self.ctx.gl.buffer(data.tobytes()),
                self.ctx.gl.buffer(m.faces.astype(np.int32).tobytes()),
                len(m.faces),
                m.uvs is not None,
            )
            self._meshes[key] = gm
        return gm

    def texture(self, node: Node) -> moderngl.Texture | None:
        tex_array = node.material.texture
        if tex_array is None:
            return None
        opacity = node.material.opacity
        key = (id(tex_array), id(opacity))
        tex = self._textures.get(key)
        if tex is None:
            if opacity is not None:  # the alpha mask in the texture's alpha (surface.glsl cuts below the cutoff)
                tex_array = np.dstack([tex_array, opacity])
            tex = self.ctx.upload(tex_array.astype(np.float32), mipmaps=True, repeat=True)
            tex.anisotropy = MAX_ANISOTROPY
            self._textures[key] = tex
        return tex

    def vao(self, program: moderngl.Program, node: Node) -> moderngl.VertexArray:
        gm = self._mesh(node)
        key = (program.glo, id(node.mesh))
        vao = self._vaos.get(key)
        if vao is None:
            # interleaved position, normal, uv; attributes the program lacks are skipped as padding
            layout = (("in_position", 3), ("in_normal", 3), ("in_uv", 2))
            names = [n for n, _ in layout if program.get(n, None) is not None]
            fmt = " ".join(f"{k}f" if n in names else f"{4 * k}x" for n, k in layout)
            vao = self.ctx.gl.vertex_array(program, [(gm.vbo, fmt, *names)], gm.ibo)
            self._vaos[key] = vao
        return vao

    def anisotropy(self, node: Node, view: View, size: tuple[int, int]) -> float:
        """The anisotropic filtering ``node``'s texture needs in ``view`` at ``size``: 1 (trilinear)
        where every pixel's footprint in it is nearly round (see :mod:`.texture_footprint`), else
        :data:`MAX_ANISOTROPY`."""
        tex, mesh = self.texture(node), node.mesh
        if tex is None or mesh.uvs is None:
            return 1.0
        if len(mesh.faces) > FOOTPRINT_MAX_FACES:
            return MAX_ANISOTROPY
        texels = np.asarray(mesh.uvs, np.float64) * np.array(tex.size, np.float64)
        ratio = footprint_anisotropy(transform_points(node.transform, mesh.vertices), mesh.faces, texels, view, size)
        return 1.0 if ratio <= ANISOTROPY_THRESHOLD else MAX_ANISOTROPY

    def bind_surface(
        self,
        program: moderngl.Program,
        index: int,
        node: Node,
        texture_unit: int = 0,
        view: View | None = None,
        size: tuple[int, int] | None = None,
    ) -> None:
        """Set the uniforms of ``shaders/surface.glsl`` for drawing ``node`` (index: its place in the
        scene; the object id is index + 1). With ``view`` and ``size``, the texture is filtered
        anisotropically only where the node's footprint needs it (:meth:`anisotropy`)."""
        mat = node.material
        set_uniform(program, "model_matrix", node.transform)
        set_uniform(
            program, "normal_matrix", np.linalg.inv(node.transform[:3, :3].astype(np.float64)).T.astype(np.float32)
        )
        set_uniform(program, "albedo", mat.colour)
        set_uniform(program, "specular", float(mat.specular))
        set_uniform(program, "shininess", float(mat.shininess))
        set_uniform(program, "emission", mat.emission)
        set_uniform(program, "object_id", float(index + 1))
        set_uniform(program, "albedo_texture", texture_unit)
        set_uniform(program, "alpha_cutoff", float(mat.alpha_cutoff) if mat.opacity is not None else 0.0)
        tex = self.texture(node)
        set_uniform(program, "has_texture", tex is not None)
        if tex is not None:
            tex.anisotropy = self.anisotropy(node, view, size) if view is not None else MAX_ANISOTROPY
            tex.use(texture_unit)

    def draw(
        self,
        program: moderngl.Program,
        set_node=None,
        front_to_back_from=None,
        only=None,
        cull_to: np.ndarray | None = None,
    ) -> None:
        """Draw every visible node (``only``: of these node indices), calling ``set_node(index, node)``
        before each. With ``front_to_back_from`` (an eye position), nearest bounding boxes first: the
        depth test then rejects hidden fragments before they are shaded. ``cull_to``: a 4×4
        view-projection matrix (row-major); nodes whose bounding box lies wholly outside its frustum
        are skipped (they would draw no pixel)."""
        keep = self.in_frustum(cull_to) if cull_to is not None else None
        order = [
            i
            for i, node in enumerate(self.scene.nodes)
            if node.visible and (only is None or i in only) and (keep is None or keep[i])
        ]
        if front_to_back_from is not None and len(order) > 1:
            distance = self.box_distances(np.asarray(front_to_back_from, np.float64))
            order.sort(key=lambda i: distance[i])
        for index in order:
            node = self.scene.nodes[index]
            if set_node is not None:
                set_node(index, node)
            self.vao(program, node).render(moderngl.TRIANGLES)

    def groups(self, key, only=None) -> dict:
        """Indices of the visible nodes (``only``: of these) grouped by ``key(index, node)``, each
        group in scene order (passes drawing each kind of surface with its own program variant)."""
        out: dict = {}
        for index, node in enumerate(self.scene.nodes):
            if node.visible and (only is None or index in only):
                out.setdefault(key(index, node), []).append(index)
        return out

    def box_distances(self, eye: np.ndarray) -> np.ndarray:
        """(N,) distance from ``eye`` to each node's world-space bounding box (0 inside it), all nodes
        at once (a per-node loop cost milliseconds a frame in Python)."""
        world = self._world_corners()
        lo, hi = world.min(axis=1), world.max(axis=1)
        return np.linalg.norm(np.maximum(0.0, np.maximum(lo - eye, eye - hi)), axis=1)

    def in_frustum(self, view_projection: np.ndarray) -> np.ndarray:
        """(N,) bool: False where all 8 corners of a node's transformed bounding box lie beyond one
        and the same clip plane (conservative: a box across a frustum corner is kept)."""
        world = self._world_corners()
        clip = np.einsum("ij,nkj->nki", np.asarray(view_projection, np.float64)[:, :3], world)
        clip += np.asarray(view_projection, np.float64)[:, 3]
        xyz, w = clip[..., :3], clip[..., 3:]
        outside = ((xyz > w).all(axis=1) | (xyz < -w).all(axis=1)).any(axis=1)
        return ~outside

    def _world_corners(self) -> np.ndarray:
        """(N, 8, 3) world-space corners of each node's mesh bounding box."""
        nodes = self.scene.nodes
        if not nodes:
            return np.zeros((0, 8, 3))
        transforms = np.stack([np.asarray(n.transform, np.float64) for n in nodes])
        return np.einsum("nij,nkj->nki", transforms[:, :3], self._corners())

    def _corners(self) -> np.ndarray:
        meshes = tuple(id(n.mesh) for n in self.scene.nodes)
        if self._corner_key != meshes:  # nodes added or meshes swapped since
            boxes = [np.asarray(n.mesh.bounds, np.float64) for n in self.scene.nodes]
            self._corner_cache = np.array(
                [
                    [[x, y, z, 1.0] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])]
                    for lo, hi in boxes
                ]
            ).reshape(len(boxes), 8, 4)
            self._corner_key = meshes
        return self._corner_cache

    @property
    def triangle_count(self) -> int:
        return sum(self._mesh(n).triangles for n in self.scene.nodes if n.visible)

    def release(self) -> None:
        for vao in self._vaos.values():
            vao.release()
        for gm in self._meshes.values():
            gm.vbo.release()
            gm.ibo.release()
        for tex in self._textures.values():
            tex.release()
        self._vaos.clear()
        self._meshes.clear()
        self._textures.clear()
