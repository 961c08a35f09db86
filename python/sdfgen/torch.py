"""sdfgen's point queries on torch tensors, differentiable with respect to the points and the mesh's
vertices.

Each function takes the mesh in one of two forms:

- ``f(points, mesh)``: ``mesh`` an :class:`sdfgen.Mesh` (built once, reused by every call);
  differentiable with respect to ``points``.
- ``f(points, vertices, faces)``: ``vertices`` a (V, 3) float tensor (it may require grad),
  ``faces`` an (F, 3) integer tensor (counter-clockwise seen from outside). Differentiable with
  respect to ``points`` and ``vertices``. The first call with these faces builds the mesh and its
  tree; a later call with the same faces and moved vertices refits that tree and keeps auto's sign
  decision while the mesh's edges hold (:meth:`sdfgen.Mesh.with_vertices`), with the same results.
- ``f(points, vertices, faces)`` with (B, V, 3) ``vertices``: B meshes of V vertices, with (F, 3)
  ``faces`` shared or (B, F, 3) faces of their own, and (B, ..., 3) ``points``, ``points[b]`` for
  mesh b; results have a first dimension B, each equal to the single call's, and gradients reach
  each mesh's vertices.
- ``f([points, ...], [mesh, ...])`` or ``f([points, ...], [vertices, ...], [faces, ...])`` (or one
  faces tensor shared): lists of meshes of any sizes, a list of results, each the single call's.
  A batch's meshes are built or refit in one pass over the thread pool, their points answered in
  another.

``points`` is a float32 or float64 tensor of shape (..., 3); results come in its dtype, on its
device (the work runs on the CPU: tensors on another device are copied there and the results
back). ``vertices`` must have the points' dtype and device. Wrong shapes, dtypes or devices raise
ValueError; bad meshes and non-finite points raise :class:`sdfgen.Error`, as the numpy queries do.

Values and gradients are exact: the nearest triangle comes from sdfgen's tree, and the closest
point on it is then measured in double precision from the given coordinates (float64 inputs are
never rounded through float32), so a distance is the one of ``Mesh.signed_distance`` (the same
float32 value, for a Mesh) and finite differences of it match the gradients:

- distance with respect to the point p: ``s * (p - c) / |p - c|``, with c the closest point and s
  the sign (1 for unsigned distances);
- distance with respect to a vertex: ``-w * s * (p - c) / |p - c|``, with w the closest point's
  barycentric weight on that vertex (a vertex not on the nearest triangle gets nothing);
- closest point: the derivative of the projection onto the closest point's feature (the face's
  plane, the edge's line, or the vertex itself) with respect to the point and its corners.

Where the distance has no derivative these are one-sided or conventional: on the surface (distance
0), ``s * (p - c) / |p - c|`` is replaced by the nearest triangle's unit face normal n (from the
given coordinates), reversed where ``sign="auto"`` finds the mesh inside out: the gradient that
``Mesh.closest``, bake's gradient channel and the C++ ``Model::query`` give there, and the limit of
the signed distance's gradient from either side of a face of a closed, outward mesh; unsigned
distances take n as their triangle winds (the limit from its front). Vertices get ``-w * n``.
At points with two or more nearest triangles or features (the medial axis) it is the gradient of
the triangle sdfgen's tree picked; across a change of the closest point's feature, one-sided.
The sign is piecewise constant and contributes no gradient. Backward passes are first order only:
one with ``create_graph=True`` (for a gradient of a gradient) raises RuntimeError.
"""
import types

import numpy as np
import torch

from . import ClosestHit, Mesh
from ._sdfgen import _meshes_batch, _nearest_terms, _nearest_terms_batch, _point_query_signs, _vertex_gradient

__all__ = ["signed_distance", "unsigned_distance", "closest_points", "closest"]


def signed_distance(points, mesh, faces=None, *, sign="auto", threads=0):
    """Signed distances (negative inside) at ``points`` (..., 3): a tensor of shape (...).

    ``sign`` as for :meth:`sdfgen.Mesh.signed_distance`;
    ``threads`` 0 for all cores. Differentiable (see the module's notes)."""
    _check_sign(sign)
    return _query(_SIGNED, points, mesh, faces, sign, threads)


def unsigned_distance(points, mesh, faces=None, *, threads=0):
    """Distances to the nearest triangle at ``points`` (..., 3): a tensor of shape (...)."""
    return _query(_UNSIGNED, points, mesh, faces, None, threads)


def closest_points(points, mesh, faces=None, *, threads=0):
    """The nearest surface point to each of ``points`` (..., 3): a tensor of shape (..., 3)."""
    return _query(_CLOSEST_POINTS, points, mesh, faces, None, threads)


def closest(points, mesh, faces=None, *, sign="auto", threads=0):
    """What the query found at ``points`` (..., 3), as an :class:`sdfgen.ClosestHit` of tensors, as
    :meth:`sdfgen.Mesh.closest` gives arrays: ``triangle`` (int64 (...), into the faces), ``point``
    (..., 3) and ``distance`` (...) (differentiable, as :func:`closest_points` and
    :func:`signed_distance`), and, as constants, ``barycentric`` (..., 3) (point's weights on the
    triangle's corners), ``sign`` (int8 (...), -1 inside, 1 outside) and ``gradient`` (..., 3)
    (the distance's gradient with respect to the point; the face normal at distance 0). One search
    serves them all."""
    _check_sign(sign)
    return _query(_CLOSEST, points, mesh, faces, sign, threads)


# What each query measures: closest points, and the whole closest-hit record.
_Kind = types.SimpleNamespace
_SIGNED, _UNSIGNED = _Kind(closest=False, hit=False), _Kind(closest=False, hit=False)
_CLOSEST_POINTS, _CLOSEST = _Kind(closest=True, hit=False), _Kind(closest=True, hit=True)


def _query(kind, points, mesh, faces, sign, threads):
    if _is_batch(mesh):
        return _batch(kind, points, mesh, faces, sign, threads)
    mesh, vertices = _mesh_of(points, mesh, faces, threads)
    return _result(kind, points, vertices, mesh, _terms(kind, [points], [vertices], [mesh], sign, threads)[0])


def _result(kind, points, vertices, mesh, terms):
    """The query's tensors from its terms: values, closest points or the closest-hit record."""
    if kind is _CLOSEST_POINTS:
        return _ClosestPoints.apply(points, vertices, mesh, terms)
    if kind is not _CLOSEST:
        return _Distance.apply(points, vertices, terms)
    shape = points.shape[:-1]
    side = np.where(np.signbit(terms.distance), -1, 1).astype(np.int8)
    return ClosestHit(triangle=torch.from_numpy(terms.triangle).reshape(shape).to(points.device),
                      point=_ClosestPoints.apply(points, vertices, mesh, terms),
                      barycentric=_like(terms.barycentric, points.shape, points),
                      distance=_Distance.apply(points, vertices, terms),
                      sign=torch.from_numpy(side).reshape(shape).to(points.device),
                      gradient=_like(terms.gradient, points.shape, points))


def _is_batch(mesh):
    return isinstance(mesh, (list, tuple)) or (isinstance(mesh, torch.Tensor) and mesh.dim() == 3)


def _batch(kind, points, mesh, faces, sign, threads):
    """B meshes in one call: (B, V, 3) vertices with (F, 3) faces shared or (B, F, 3) faces of
    their own and (B, ..., 3) points, results stacked; or lists of meshes (sdfgen.Mesh, or vertices
    with a list of faces or one faces tensor shared) and of points, results in a list. The meshes
    are built or refit in one pass over the thread pool and all their points answered in another
    (each mesh's results bit for bit its single call's)."""
    if isinstance(mesh, torch.Tensor):
        point_list, vertex_list, face_list = _unstack(points, mesh, faces)
    else:
        point_list, vertex_list, face_list = _listed(points, mesh, faces)
    checked = [_mesh_of(p, v, f, threads, build=False) for p, v, f in zip(point_list, vertex_list, face_list)]
    vertex_list = [v for _, v in checked]
    meshes = [m for m, _ in checked]
    if meshes and meshes[0] is None:
        meshes = _tensor_batch(vertex_list, face_list, threads)
    terms = _terms(kind, point_list, vertex_list, meshes, sign, threads)
    results = [_result(kind, *args) for args in zip(point_list, vertex_list, meshes, terms)]
    if not isinstance(mesh, torch.Tensor):
        return results
    if kind is _CLOSEST:
        return ClosestHit(*(torch.stack(field) for field in zip(*results)))
    return torch.stack(results)


def _unstack(points, vertices, faces):
    """(B, V, 3) vertices, their faces and (B, ..., 3) points as lists of each mesh's."""
    if not isinstance(points, torch.Tensor) or points.dim() < 2 or points.shape[0] != vertices.shape[0]:
        shape = tuple(points.shape) if isinstance(points, torch.Tensor) else type(points).__name__
        raise ValueError(f"batched vertices ({tuple(vertices.shape)}) take points of shape (B, ..., 3) with B = "
                         f"{vertices.shape[0]}, not {shape}")
    if not isinstance(faces, torch.Tensor) or faces.dim() not in (2, 3) or (faces.dim() == 3 and faces.shape[0] != vertices.shape[0]):
        shape = tuple(faces.shape) if isinstance(faces, torch.Tensor) else type(faces).__name__
        raise ValueError(f"batched vertices ({tuple(vertices.shape)}) take faces of shape (F, 3) or "
                         f"({vertices.shape[0]}, F, 3), not {shape}")
    count = len(vertices)
    return list(points.unbind(0)), list(vertices.unbind(0)), [faces] * count if faces.dim() == 2 else list(faces.unbind(0))


def _listed(points, meshes, faces):
    """A list of meshes (sdfgen.Mesh, or vertices with their faces) with a list of points."""
    count = len(meshes)
    if not isinstance(points, (list, tuple)) or len(points) != count:
        given = f"{len(points)} points" if isinstance(points, (list, tuple)) else type(points).__name__
        raise ValueError(f"a list of {count} meshes takes a list of {count} points tensors, not {given}")
    if faces is None or isinstance(faces, torch.Tensor):
        face_list = [faces] * count
    elif isinstance(faces, (list, tuple)) and len(faces) == count:
        face_list = list(faces)
    else:
        given = f"{len(faces)} faces" if isinstance(faces, (list, tuple)) else type(faces).__name__
        raise ValueError(f"a list of {count} vertices takes a list of {count} faces tensors or one shared, not {given}")
    if len({isinstance(m, Mesh) for m in meshes}) > 1:
        raise ValueError("a list of meshes must be all sdfgen.Mesh or all vertices tensors, not both")
    return list(points), list(meshes), face_list


def _check_sign(sign):
    if not isinstance(sign, str):
        raise ValueError(f"sign must be a string ({', '.join(_point_query_signs)}), not {type(sign).__name__}")


def _mesh_of(points, mesh, faces, threads, build=True):
    """Checks the arguments; returns the sdfgen.Mesh (None for tensors unless `build`) and the
    vertices tensor (None for a Mesh)."""
    if not isinstance(points, torch.Tensor):
        raise ValueError(f"points must be a torch.Tensor of shape (..., 3), not {type(points).__name__}")
    if points.dtype not in (torch.float32, torch.float64):
        raise ValueError(f"points must be float32 or float64, not {points.dtype}")
    if points.dim() < 1 or points.shape[-1] != 3:
        raise ValueError(f"points must have shape (..., 3), not {tuple(points.shape)}")
    if points.device.type == "meta":
        raise ValueError("points are on the meta device: they hold no values")
    if isinstance(mesh, Mesh):
        if faces is not None:
            raise ValueError("give either an sdfgen.Mesh or vertices and faces, not both")
        return mesh, None
    vertices = mesh
    if not isinstance(vertices, torch.Tensor) or not isinstance(faces, torch.Tensor):
        raise ValueError("the mesh must be an sdfgen.Mesh, or vertices and faces as torch tensors")
    if vertices.dim() != 2 or vertices.shape[1] != 3:
        raise ValueError(f"vertices must have shape (V, 3), not {tuple(vertices.shape)}")
    if vertices.dtype != points.dtype:
        raise ValueError(f"vertices must have the points' dtype ({points.dtype}), not {vertices.dtype}")
    if vertices.device != points.device:
        raise ValueError(f"vertices must be on the points' device ({points.device}), not {vertices.device}")
    if faces.dim() != 2 or faces.shape[1] != 3:
        raise ValueError(f"faces must have shape (F, 3), not {tuple(faces.shape)}")
    if faces.dtype.is_floating_point or faces.dtype.is_complex or faces.dtype == torch.bool:
        raise ValueError(f"faces must be an integer tensor, not {faces.dtype}")
    return (_tensor_mesh(_cpu(vertices), _cpu(faces), threads) if build else None), vertices


# The meshes built from tensors, the latest last, each with its vertex count and a copy of its faces:
# a call with the same faces and moved vertices (an optimisation step) refits the previous mesh's
# tree and keeps its sign decision (Mesh.with_vertices) instead of building a new mesh. Found by
# comparing the faces (a pass at memory speed), not by hashing them. A few topologies are kept.
_tensor_meshes = []
_TENSOR_MESHES_KEPT = 4


def _tensor_mesh(vertices, faces, threads):
    previous = None
    for i, (vertex_count, kept_faces, kept) in enumerate(_tensor_meshes):
        if vertex_count == len(vertices) and np.array_equal(kept_faces, faces):
            previous = kept
            del _tensor_meshes[i]
            break
    if previous is None:
        mesh = Mesh(vertices, faces, name="<tensors>", threads=threads)
        kept_faces = faces.copy()  # `faces` may view the caller's tensor, which may change
    else:
        mesh = previous.with_vertices(vertices, threads=threads)
    # Kept only while no zero-area triangle is dropped: with_vertices keeps the mesh's own faces.
    if mesh.triangle_count == len(faces):
        _tensor_meshes.append((len(vertices), kept_faces, mesh))
        del _tensor_meshes[:-_TENSOR_MESHES_KEPT]
    return mesh


# The batches built from tensors, the latest last, each with its meshes' vertex counts and copies
# of their faces: a batch with the same faces refits each of the previous batch's meshes (as
# _tensor_mesh does for one mesh), all in one pass.
_tensor_batches = []
_TENSOR_BATCHES_KEPT = 2


def _tensor_batch(vertices, faces, threads):
    vertices = [_cpu(v) for v in vertices]
    by_tensor = {}  # faces shared by the meshes are read, copied and compared once
    for f in faces:
        if id(f) not in by_tensor:
            by_tensor[id(f)] = _cpu(f)
    face_arrays = [by_tensor[id(f)] for f in faces]
    counts = tuple(len(v) for v in vertices)
    previous, kept_faces = [None] * len(vertices), None
    for i, (kept_counts, kept, kept_meshes) in enumerate(_tensor_batches):
        compared = {}
        if kept_counts == counts and all(_same_faces(k, f, compared) for k, f in zip(kept, face_arrays)):
            # Kept only while no zero-area triangle is dropped: with_vertices keeps the mesh's own faces.
            previous = [m if m.triangle_count == len(f) else None for m, f in zip(kept_meshes, face_arrays)]
            kept_faces = kept
            del _tensor_batches[i]
            break
    if kept_faces is None:
        copies = {}  # the faces may view the caller's tensors, which may change
        for f in face_arrays:
            if id(f) not in copies:
                copies[id(f)] = f.copy()
        kept_faces = [copies[id(f)] for f in face_arrays]
    meshes = _meshes_batch(previous, vertices, face_arrays, name="<tensors>", threads=threads)
    _tensor_batches.append((counts, kept_faces, meshes))
    del _tensor_batches[:-_TENSOR_BATCHES_KEPT]
    return meshes


def _same_faces(kept, faces, compared):
    key = (id(kept), id(faces))
    if key not in compared:
        compared[key] = np.array_equal(kept, faces)
    return compared[key]


def _cpu(tensor):
    """The tensor's values as a numpy array (a view when the tensor is on the CPU and contiguous)."""
    return tensor.detach().to("cpu").contiguous().numpy()


def _flat_points(points):
    return _cpu(points).reshape(-1, 3)


def _vertex_coordinates(vertices):
    """float64 (V, 3) numpy coordinates of a vertices tensor, or None (the Mesh's own)."""
    return None if vertices is None else _cpu(vertices.detach().to(torch.float64))


def _like(values, shape, reference):
    """A numpy result as a tensor of `shape` in the dtype and on the device of `reference`."""
    return torch.from_numpy(values).reshape(shape).to(dtype=reference.dtype, device=reference.device)


def _first_order_only():
    """Backward passes give first derivatives as constants: with create_graph=True (grad mode on
    in backward) a gradient of them would silently miss the second derivatives, so refuse."""
    if torch.is_grad_enabled():
        raise RuntimeError("sdfgen.torch gives first derivatives only: backward with create_graph=True "
                           "(a gradient of a gradient) is not supported")


def _terms(kind, points, vertices, meshes, sign, threads):
    """The nearest-point terms of one search per mesh (python/nearest.hpp) for lists of points,
    vertices (None for a Mesh's own) and meshes, those the values and gradients asked for need;
    None for the others. A batch's meshes are measured in one call."""
    grad = torch.is_grad_enabled()
    wanted = [(grad and p.requires_grad, grad and v is not None and v.requires_grad) for p, v in zip(points, vertices)]
    wants_points, wants_vertices = any(p for p, _ in wanted), any(v for _, v in wanted)
    options = dict(sign=sign, gradient=wants_points or wants_vertices or kind.hit, closest=kind.closest,
                   features=wants_vertices or (kind.closest and wants_points), hit=kind.hit, threads=threads)
    flat = [_flat_points(p) for p in points]
    coordinates = [_vertex_coordinates(v) for v in vertices]
    if len(meshes) == 1:
        found = [_nearest_terms(meshes[0], flat[0], coordinates[0], **options)]
    else:
        found = _nearest_terms_batch(meshes, flat, coordinates, **options)
    names = ("distance", "gradient", "closest", "corners", "weights", "feature_size", "triangle", "barycentric")
    return [types.SimpleNamespace(**dict(zip(names, terms)), wants_points=p, wants_vertices=v) for terms, (p, v) in zip(found, wanted)]


class _Distance(torch.autograd.Function):
    """Signed (a sign method given) or unsigned distances, with gradients from the exact terms."""

    @staticmethod
    def forward(ctx, points, vertices, terms):
        # The terms' own record of the gradients wanted (grad mode is off in forward, and
        # needs_input_grad says nothing of it).
        wants_points, wants_vertices = terms.wants_points, terms.wants_vertices
        if wants_points or wants_vertices:
            ctx.points_like = (points.shape, points.dtype, points.device)
            ctx.vertices_like = None if vertices is None else (vertices.shape, vertices.dtype, vertices.device)
            saved = [torch.from_numpy(terms.gradient)]
            if wants_vertices:
                saved += [torch.from_numpy(terms.corners), torch.from_numpy(terms.weights)]
            ctx.save_for_backward(*saved)
        return _like(terms.distance, points.shape[:-1], points)

    @staticmethod
    def backward(ctx, grad):
        _first_order_only()
        gradient, *features = ctx.saved_tensors
        g = grad.detach().to(device="cpu", dtype=torch.float64).reshape(-1, 1)
        grad_points = grad_vertices = None
        if ctx.needs_input_grad[0]:
            shape, dtype, device = ctx.points_like
            grad_points = (gradient * g).reshape(shape).to(dtype=dtype, device=device)
        if ctx.needs_input_grad[1]:
            corners, weights = features
            shape, dtype, device = ctx.vertices_like
            # The closest point moves with its triangle's corners by its weights: d(distance)/dv = -w * gradient,
            # summed per vertex in one pass (no (P, 3, 3) temporaries to allocate and fill).
            summed = _vertex_gradient(corners.numpy(), weights.numpy(), gradient.numpy(), g.reshape(-1).contiguous().numpy(), shape[0])
            grad_vertices = torch.from_numpy(summed).to(dtype=dtype, device=device)
        return grad_points, grad_vertices, None


class _ClosestPoints(torch.autograd.Function):
    """Closest surface points; backward differentiates the projection onto each point's feature."""

    @staticmethod
    def forward(ctx, points, vertices, mesh, terms):
        if terms.wants_points or terms.wants_vertices:
            ctx.mesh = mesh
            ctx.save_for_backward(points, vertices, torch.from_numpy(terms.corners), torch.from_numpy(terms.feature_size))
        return _like(terms.closest, points.shape, points)

    @staticmethod
    def backward(ctx, grad):
        _first_order_only()
        points, vertices, corners, feature_size = ctx.saved_tensors
        wants_points, wants_vertices = ctx.needs_input_grad[0], ctx.needs_input_grad[1]
        with torch.enable_grad():
            p = points.detach().to(device="cpu", dtype=torch.float64).reshape(-1, 3).requires_grad_(wants_points)
            if vertices is None:
                v = torch.from_numpy(ctx.mesh.vertices)
            else:
                v = vertices.detach().to(device="cpu", dtype=torch.float64).requires_grad_(wants_vertices)
            closest = _project_onto_features(p, v, corners, feature_size)
            inputs = [x for x, wanted in ((p, wants_points), (v, wants_vertices)) if wanted]
            if closest.requires_grad:  # else every closest point is a vertex of a fixed mesh
                upstream = grad.detach().to(device="cpu", dtype=torch.float64).reshape(-1, 3)
                found = torch.autograd.grad(closest, inputs, upstream, allow_unused=True)
            else:
                found = [None] * len(inputs)
            grads = iter(torch.zeros_like(x) if g is None else g for x, g in zip(inputs, found))
        grad_points = next(grads).reshape(points.shape).to(dtype=points.dtype, device=points.device) if wants_points else None
        grad_vertices = next(grads).to(dtype=vertices.dtype, device=vertices.device) if wants_vertices else None
        return grad_points, grad_vertices, None, None


def _project_onto_features(p, v, corners, feature_size):
    """The closest points again, as differentiable functions of p and v: each point projected onto
    its closest feature (corners spanning it first: 1 vertex, 2 edge, 3 face)."""
    a, b, c = (v[corners[:, k]] for k in range(3))
    closest = a  # on a vertex
    edge = torch.nonzero(feature_size == 2).reshape(-1)
    if len(edge):
        ea, d = a[edge], b[edge] - a[edge]
        t = ((p[edge] - ea) * d).sum(-1, keepdim=True) / (d * d).sum(-1, keepdim=True)
        closest = closest.index_put((edge,), ea + t * d)
    face = torch.nonzero(feature_size == 3).reshape(-1)
    if len(face):
        fa, fp = a[face], p[face]
        n = torch.cross(b[face] - fa, c[face] - fa, dim=-1)
        closest = closest.index_put((face,), fp - ((fp - fa) * n).sum(-1, keepdim=True) / (n * n).sum(-1, keepdim=True) * n)
    return closest
