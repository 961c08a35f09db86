// The sdfgen Python module (pybind11, numpy): meshes, bakes, point queries and samples over the
// library's Model. Long calls run on a worker thread with the GIL released; the calling thread
// wakes every 50 ms to pass progress to Python and to check for Ctrl+C, which cancels the work.
#include "sdfgen/sdfgen.hpp"
#include "sdfgen/sample.hpp"
#include "nearest.hpp"
#include "core/runtime/parallel.hpp"
#if SDFGEN_PYTHON_GPU
#include "gpu/devices.hpp"
#endif

#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <deque>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <optional>
#include <chrono>
#include <future>
#include <limits>
#include <memory>
#include <type_traits>

namespace py = pybind11;

namespace sdfgen::python {

namespace {

// sdfgen.Warning, the category of every warning the module gives (set when the module loads).
PyObject* warningClass = nullptr;

// Point calls (queries, samples) of fewer points than this are small: with threads=0 they run on
// the calling thread alone (the GIL released), with no watcher thread and no worker pool to wake,
// which for 100 points costs more than the work (bench/python_bench.py --small-calls). The one
// place that decides it; results never depend on the thread count.
constexpr std::size_t kSmallCallPoints = 2048;

// Runs work(control) on another thread with the GIL released. Ctrl+C (or an exception from the
// progress callback) raises the cancel flag, waits for the work to stop and re-raises in Python.
// The warnings the work gives (RunControl::warn) are issued as sdfgen.Warning when it is done.
// `points`: the call's size, for point calls (small ones run inline on one thread, see above).
template <class Work>
auto runReleased(Work&& work, int threads, const py::object& progress = py::none(),
                 std::size_t points = std::numeric_limits<std::size_t>::max()) {
    // Checked here as the command line checks --threads, before any thread pool is set up.
    if (threads < 0 || threads > kMaxThreads) {
        throw Error("threads must be from 0 (all cores) to " + std::to_string(kMaxThreads) + ", not " + std::to_string(threads));
    }
    std::vector<std::string> warnings; // written by the worker, read once it is done
    auto issueWarnings = [&warnings] {
        for (const std::string& warning : warnings) {
            if (PyErr_WarnEx(warningClass, warning.c_str(), 1) != 0) throw py::error_already_set(); // a filter made it an error
        }
    };
    if (points < kSmallCallPoints && progress.is_none()) {
        RunControl control;
        control.threads = threads == 0 ? 1 : threads;
        control.warn = [&warnings](const std::string& warning) { warnings.push_back(warning); };
        using Result = decltype(work(control));
        std::optional<Result> value;
        {
            py::gil_scoped_release release;
            value.emplace(work(control));
        }
        issueWarnings();
        return std::move(*value);
    }
    std::atomic<bool> cancel{false};
    std::atomic<double> fraction{0.0};
    RunControl control;
    control.threads = threads;
    control.cancel = &cancel;
    control.warn = [&warnings](const std::string& warning) { warnings.push_back(warning); };
    if (!progress.is_none()) control.progress = [&fraction](double f) { fraction.store(f, std::memory_order_relaxed); };
    using Result = decltype(work(control));
    std::future<Result> result;
    bool interrupted = false;
    {
        py::gil_scoped_release release;
        result = std::async(std::launch::async, [&work, &control] { return work(control); });
        double reported = -1.0;
        while (result.wait_for(std::chrono::milliseconds(50)) != std::future_status::ready) {
            py::gil_scoped_acquire acquire;
            if (PyErr_CheckSignals() != 0) {
                interrupted = true; // the exception (KeyboardInterrupt) stays set on this thread
            } else if (!progress.is_none()) {
                const double f = fraction.load(std::memory_order_relaxed);
                if (f != reported) {
                    reported = f;
                    try {
                        progress(f);
                    } catch (py::error_already_set& e) {
                        e.restore();
                        interrupted = true;
                    }
                }
            }
            if (interrupted) break;
        }
        if (interrupted) {
            cancel = true;
            result.wait();
        }
    }
    if (interrupted) {
        try {
            result.get();
        } catch (...) {
            // Cancelled, or whatever the work threw as it stopped: the interrupt is what the caller sees.
        }
        throw py::error_already_set();
    }
    Result value = result.get(); // rethrows the work's Error, translated below
    issueWarnings();
    if (!progress.is_none()) progress(1.0);
    return value;
}

// A numpy array that owns `values` (moved into a capsule), with the given shape in C order.
template <class T>
py::array_t<T> toNumpy(std::vector<T>&& values, std::vector<py::ssize_t> shape) {
    auto* owned = new std::vector<T>(std::move(values));
    py::capsule free(owned, [](void* p) { delete static_cast<std::vector<T>*>(p); });
    return py::array_t<T>(shape, owned->data(), free);
}

// "a, b or c": a registry's names, for messages and docstrings.
template <class Id>
std::string namesOf(const std::vector<Choice<Id>>& choices) {
    std::string names;
    for (std::size_t i = 0; i < choices.size(); ++i) names += (i == 0 ? "" : i + 1 == choices.size() ? " or " : ", ") + std::string(choices[i].name);
    return names;
}

// The choice a keyword argument names; ValueError listing the registry's names.
template <class Id>
Id choose(const std::vector<Choice<Id>>& choices, const char* what, const std::string& name) {
    for (const Choice<Id>& choice : choices) {
        if (name == choice.name) return choice.id;
    }
    throw py::value_error(std::string(what) + " must be " + namesOf(choices) + " (got '" + name + "')");
}

SignMethod signFrom(const std::string& name) { return choose(signMethodChoices(), "sign", name); }

// The registry's channel names after `first`, `separator` between them, `last` before the last one.
std::string channelNames(const std::string& separator, const std::string& last, const std::string& first) {
    const std::vector<ChannelInfo>& infos = channelInfos();
    std::string text = first;
    for (std::size_t c = 0; c < infos.size(); ++c) text += (c == 0 ? "" : c + 1 == infos.size() ? last : separator) + std::string(infos[c].name);
    return text;
}

// Channels from "sdf,gradient" or ["sdf", "gradient"]; ValueError for an unknown name.
Channels channelsFrom(const py::object& names) {
    std::string list;
    if (py::isinstance<py::str>(names)) {
        list = names.cast<std::string>();
    } else {
        for (const py::handle name : names) list += (list.empty() ? "" : ",") + name.cast<std::string>();
    }
    try {
        return parseChannels(list);
    } catch (const Error& e) {
        throw py::value_error(e.what());
    }
}

py::dict checkToDict(const MeshCheck& c) {
    py::dict d;
    d["boundary_edges"] = c.boundaryEdges;
    d["non_manifold_edges"] = c.nonManifoldEdges;
    d["inconsistent_edges"] = c.inconsistentEdges;
    d["non_manifold_vertices"] = c.nonManifoldVertices;
    d["self_intersections"] = c.selfIntersectionsSearched ? py::object(py::int_(c.selfIntersections)) : py::object(py::none());
    d["closed_and_clean"] = c.closedAndClean();
    d["description"] = c.describe();
    return d;
}

// sdfgen.ClosestHit, the record Mesh.closest and sdfgen.torch.closest return (a namedtuple, made when the module loads;
// a handle, never released, as warningClass: the module lives as long as the interpreter).
py::handle closestHitClass;

// A mesh ready for queries: the library's Model, shared by every Python reference.
struct PyMesh {
    std::shared_ptr<const Model> model;
};

// Pickling (pickle, copy.deepcopy, torch.save, DataLoader workers): the mesh as it was built, its
// local-frame float positions, frame, triangles, normals and bounds byte for byte, so that the
// unpickled mesh's tree and every query are bit-identical (nothing is measured again).
constexpr int kMeshStateVersion = 1;

template <class T>
py::bytes bytesOf(const std::vector<T>& values) {
    return py::bytes(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(T));
}

template <class T>
std::vector<T> vectorOf(const py::bytes& bytes, const char* what) {
    const std::string data = bytes;
    if (data.size() % sizeof(T) != 0) throw py::value_error(std::string("Mesh state: ") + what + " has a partial element");
    std::vector<T> values(data.size() / sizeof(T));
    if (!values.empty()) std::memcpy(values.data(), data.data(), data.size());
    return values;
}

py::tuple meshState(const PyMesh& m) {
    const Mesh& mesh = m.model->mesh();
    return py::make_tuple(kMeshStateVersion, mesh.source, py::make_tuple(mesh.origin.x, mesh.origin.y, mesh.origin.z), mesh.unit,
                          bytesOf(mesh.positions), bytesOf(mesh.triangles), bytesOf(mesh.faceNormals),
                          bytesOf(std::vector<glm::vec3>{mesh.bounds.min, mesh.bounds.max}), mesh.droppedDegenerate, mesh.warnings);
}

PyMesh meshFromState(const py::tuple& state) {
    if (state.size() != 10 || state[0].cast<int>() != kMeshStateVersion) {
        throw py::value_error("not a pickled sdfgen.Mesh of this version (state version " + std::to_string(kMeshStateVersion) + ")");
    }
    Mesh mesh;
    mesh.source = state[1].cast<std::string>();
    const auto origin = state[2].cast<std::array<double, 3>>();
    mesh.origin = glm::dvec3(origin[0], origin[1], origin[2]);
    mesh.unit = state[3].cast<double>();
    mesh.positions = vectorOf<glm::vec3>(state[4], "positions");
    mesh.triangles = vectorOf<glm::uvec3>(state[5], "triangles");
    mesh.faceNormals = vectorOf<glm::vec3>(state[6], "normals");
    const std::vector<glm::vec3> bounds = vectorOf<glm::vec3>(state[7], "bounds");
    mesh.droppedDegenerate = state[8].cast<std::size_t>();
    mesh.warnings = state[9].cast<std::vector<std::string>>();
    if (bounds.size() != 2 || mesh.faceNormals.size() != mesh.triangles.size() || mesh.triangles.empty()) {
        throw py::value_error("Mesh state: inconsistent sizes");
    }
    mesh.bounds = {bounds[0], bounds[1]};
    for (const glm::uvec3& t : mesh.triangles) {
        for (int c = 0; c < 3; ++c) {
            if (t[c] >= mesh.positions.size()) throw py::value_error("Mesh state: a vertex index out of range");
        }
    }
    PyMesh result;
    // The mesh's warnings were issued when it was first built; they stay in Mesh.warnings only.
    py::gil_scoped_release release;
    result.model = std::make_shared<const Model>(std::move(mesh));
    return result;
}

// ValueError unless `array` holds real numbers: a float or integer dtype. A cast to float64 would
// silently drop a complex number's imaginary part, and read bools or strings as numbers.
void checkReal(const py::array& array, const char* what) {
    const char kind = array.dtype().kind();
    if (kind != 'f' && kind != 'i' && kind != 'u') {
        throw py::value_error(std::string(what) + " must be real numbers (a float or integer array), not " +
                              py::str(array.dtype()).cast<std::string>());
    }
}

// Points as a C-contiguous float64 (P, 3) array, from any (..., 3) array of real numbers; `shape`
// gets the leading dims.
py::array_t<double, py::array::c_style> pointsFrom(const py::array& input, std::vector<py::ssize_t>& shape) {
    checkReal(input, "points");
    auto points = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(input);
    if (!points || points.ndim() < 1 || points.shape(points.ndim() - 1) != 3) {
        throw py::value_error("points must be an array of shape (P, 3) (or (..., 3)) of numbers");
    }
    shape.assign(points.shape(), points.shape() + points.ndim() - 1);
    return points;
}

template <class T>
py::array_t<T> query(const PyMesh& mesh, const py::array& input, SignMethod sign, int threads, T* PointQueryOutputs::*member,
                     int components) {
    std::vector<py::ssize_t> shape;
    const auto points = pointsFrom(input, shape);
    const std::size_t count = std::size_t(points.size() / 3);
    std::vector<T> out(count * std::size_t(components));
    const double* data = points.data();
    runReleased(
        [&](const RunControl& control) {
            PointQueryOutputs outputs;
            outputs.*member = out.data();
            mesh.model->query(data, count, outputs, sign, control);
            return 0;
        },
        threads, py::none(), count);
    if (components > 1) shape.push_back(components);
    return toNumpy(std::move(out), shape);
}

// (M, 3) int64 triangles of the mesh.
py::array_t<std::int64_t> facesOf(const Mesh& mesh) {
    std::vector<std::int64_t> faces(3 * mesh.triangles.size());
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
        for (int c = 0; c < 3; ++c) faces[3 * t + std::size_t(c)] = mesh.triangles[t][c];
    }
    return toNumpy(std::move(faces), {py::ssize_t(mesh.triangles.size()), 3});
}

// Vertices read from Python (the GIL held) with their triangles, for a model built on a worker.
// Float input keeps its float values (buildMesh warns when float cannot resolve the mesh).
struct MeshInput {
    std::string name;
    bool single = false; // float32 input: `floats`, else `doubles`
    std::vector<glm::vec3> floats;
    std::vector<glm::dvec3> doubles;
    std::vector<glm::uvec3> triangles;
    const Model* previous = nullptr; // the model whose vertices these are, moved (Model::refit), or null
};

// `vertices` (N, 3) float32 or float64.
MeshInput meshInput(const py::array& vertices, std::vector<glm::uvec3> triangles, const std::string& name, const Model* previous) {
    checkReal(vertices, "vertices");
    MeshInput input;
    input.name = name;
    input.triangles = std::move(triangles);
    input.previous = previous;
    input.single = vertices.dtype().is(py::dtype::of<float>());
    if (input.single) {
        const auto v = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(vertices);
        input.floats.resize(std::size_t(v.shape(0)));
        std::memcpy(input.floats.data(), v.data(), input.floats.size() * sizeof(glm::vec3));
    } else {
        const auto v = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(vertices);
        if (!v) throw py::value_error("vertices must be numbers");
        input.doubles.resize(std::size_t(v.shape(0)));
        std::memcpy(input.doubles.data(), v.data(), input.doubles.size() * sizeof(glm::dvec3));
    }
    return input;
}

// The model of `input` (its arrays moved out): its previous model refit where its vertices group
// as before, else built.
std::shared_ptr<const Model> modelOf(MeshInput& input, const RunControl& control) {
    Mesh built = input.single ? buildMesh(input.name, input.floats, std::move(input.triangles))
                              : buildMesh(input.name, std::move(input.doubles), std::move(input.triangles));
    return std::make_shared<const Model>(input.previous ? input.previous->refit(std::move(built), control) : Model(std::move(built), control));
}

// The models of every input in one pass over the thread pool: meshes of few triangles (whose
// builds and refits are a few short loops, shorter than waking the pool for each) side by side on
// one thread each, larger ones alone on all of control's threads. Results never depend on the
// thread count. Warnings reach control.warn in input order.
std::vector<std::shared_ptr<const Model>> modelsOf(std::vector<MeshInput>& inputs, const RunControl& control) {
    constexpr std::size_t kMeshAlone = std::size_t(1) << 16; // triangles
    std::vector<std::shared_ptr<const Model>> models(inputs.size());
    runSideBySide(
        inputs.size(), [&](std::size_t b) { return inputs[b].triangles.size() >= kMeshAlone; },
        [&](std::size_t b, const RunControl& part) { models[b] = modelOf(inputs[b], part); }, control);
    return models;
}

// The model of (N, 3) float32 or float64 `vertices` and `triangles`. `previous`: the model whose
// vertices these are, moved (Model::refit: refit where its vertices group as before), or null.
PyMesh meshFromVertices(const py::array& vertices, std::vector<glm::uvec3> triangles, const std::string& name, int threads,
                        const Model* previous = nullptr) {
    MeshInput input = meshInput(vertices, std::move(triangles), name, previous);
    PyMesh mesh;
    mesh.model = runReleased([&](const RunControl& control) { return modelOf(input, control); }, threads);
    return mesh;
}

// (M, 3) integer `faces` as triangles over `vertexCount` vertices (indices checked only for their type's range here).
std::vector<glm::uvec3> trianglesFrom(const py::array& faces, py::ssize_t vertexCount, const std::string& name) {
    if (faces.ndim() != 2 || faces.shape(1) != 3) throw py::value_error("faces must have shape (M, 3)");
    if (!py::isinstance<py::array_t<std::int64_t>>(faces) && faces.dtype().kind() != 'i' && faces.dtype().kind() != 'u') {
        throw py::value_error("faces must be an integer array");
    }
    // Unsigned indices are read as unsigned: one above 2^63 is shown as it is, never as a negative.
    std::vector<glm::uvec3> triangles(std::size_t(faces.shape(0)));
    auto readIndices = [&](auto integer) {
        using Index = decltype(integer);
        const auto f = py::array_t<Index, py::array::c_style | py::array::forcecast>::ensure(faces);
        const Index* fd = f.data();
        for (std::size_t t = 0; t < triangles.size(); ++t) {
            for (int c = 0; c < 3; ++c) {
                const Index index = fd[3 * t + std::size_t(c)];
                if ((std::is_signed_v<Index> && std::int64_t(index) < 0) || std::uint64_t(index) > std::numeric_limits<std::uint32_t>::max()) {
                    throw Error(name + ": face " + std::to_string(t) + " has vertex index " + std::to_string(index) +
                                ", outside 0.." + std::to_string(vertexCount - 1));
                }
                triangles[t][c] = std::uint32_t(index);
            }
        }
    };
    if (faces.dtype().kind() == 'u') readIndices(std::uint64_t{});
    else readIndices(std::int64_t{});
    return triangles;
}

void checkVertexShape(const py::array& vertices) {
    if (vertices.ndim() != 2 || vertices.shape(1) != 3) throw py::value_error("vertices must have shape (N, 3)");
}

PyMesh meshFromArrays(const py::array& vertices, const py::array& faces, const std::string& name, int threads) {
    checkVertexShape(vertices);
    checkReal(vertices, "vertices");
    return meshFromVertices(vertices, trianglesFrom(faces, vertices.shape(0), name), name, threads);
}

// Mesh.with_vertices' check: `vertices` are (V, 3), the mesh's vertex count.
void checkMovedVertices(const Mesh& mesh, const py::array& vertices) {
    if (vertices.ndim() != 2 || vertices.shape(1) != 3 || std::size_t(vertices.shape(0)) != mesh.positions.size()) {
        throw py::value_error("vertices must be the mesh's " + std::to_string(mesh.positions.size()) + " vertices, of shape (V, 3)");
    }
}

// A baked or loaded field; `values` views its buffer.
struct PyField {
    Field field;
    std::optional<BakeResult> bake; // what the bake decided (absent for a loaded field)
};

// A narrow-band field (a band bake, or a sparse file); `brick_values` and `inside_boxes` view its buffers.
struct PySparseField {
    explicit PySparseField(SparseField band, std::optional<BakeResult> baked = std::nullopt) : field(std::move(band)), bake(std::move(baked)) {}
    SparseField field;
    std::optional<BakeResult> bake; // what the bake decided (absent for a loaded field)
    // The bricks' first samples (field.bricks * 8), as the sparse .npz stores them: made on first use.
    std::vector<int> brickOrigins;
};

py::tuple tuple3(const glm::dvec3& v) { return py::make_tuple(v.x, v.y, v.z); }

// A baked or loaded field as Python gets it: a SparseField for a band field, a Field otherwise.
py::object fieldObject(AnyField field, std::optional<BakeResult> bake) {
    if (field.isBand()) return py::cast(std::make_unique<PySparseField>(std::move(field.band()), std::move(bake)));
    auto result = std::make_unique<PyField>();
    result->field = std::move(field.dense());
    result->bake = std::move(bake);
    return py::cast(std::move(result));
}

const FieldHeader& headerOf(const Field& field) { return field; }
const FieldHeader& headerOf(const SparseField& field) { return field.header(); }

// The grid, provenance and bake decisions that Field and SparseField both have.
template <class Py>
void addFieldInfo(py::class_<Py>& cls) {
    cls.def_property_readonly("dims", [](const Py& f) {
           const glm::ivec3 d = headerOf(f.field).grid.dims;
           return py::make_tuple(d.x, d.y, d.z);
       })
        .def_property_readonly("origin", [](const Py& f) { return tuple3(headerOf(f.field).grid.origin); },
                               "The grid's minimum corner; sample (i, j, k) is at origin + (i + 1/2, j + 1/2, k + 1/2) * voxel_size")
        .def_property_readonly("voxel_size", [](const Py& f) { return headerOf(f.field).grid.voxel; })
        .def_property_readonly("source", [](const Py& f) { return headerOf(f.field).source; })
        .def_property_readonly("method", [](const Py& f) { return headerOf(f.field).method; })
        .def_property_readonly("parameters", [](const Py& f) {
            py::dict d;
            for (const auto& [key, value] : headerOf(f.field).parameters) d[py::str(key)] = value;
            return d;
        })
        .def_property_readonly("sign", [](const Py& f) { return headerOf(f.field).parameter("sign"); }, "The sign method used, e.g. 'auto/winding'")
        .def_property_readonly("device", [](const Py& f) { return f.bake ? py::object(py::str(f.bake->deviceReason)) : py::object(py::none()); },
                               "Where the bake ran and why, e.g. 'cpu: asked for' (None for a loaded field)")
        .def_property_readonly("warnings", [](const Py& f) { return f.bake ? f.bake->warnings : std::vector<std::string>{}; },
                               "The bake's warnings, one line each (also issued as sdfgen.Warning); empty for a loaded field")
        .def_property_readonly("sign_reason", [](const Py& f) { return f.bake ? py::object(py::str(f.bake->signReason)) : py::object(py::none()); })
        .def_property_readonly("check", [](const Py& f) {
            return f.bake && f.bake->checked ? py::object(checkToDict(f.bake->check)) : py::object(py::none());
        }, "The mesh check made for sign='auto', as a dict (None otherwise); its 'self_intersections' is None when holes or bad "
   "edges decided the sign and the search was skipped");
}

// The channel `name` of the field `self` as an (nx, ny, nz) or, for a vector, (nx, ny, nz, width)
// view of its planar buffer (no copy; keeps the field alive); None when it was not baked.
template <class T>
py::object planarView(const py::object& self, const T* planes, int width) {
    const glm::ivec3 d = self.cast<const PyField&>().field.grid.dims;
    const py::ssize_t item = sizeof(T), nx = d.x, ny = d.y, nz = d.z;
    std::vector<py::ssize_t> shape{nx, ny, nz}, strides{item, item * nx, item * nx * ny};
    if (width > 1) shape.push_back(width), strides.push_back(item * nx * ny * nz);
    return py::array_t<T>(shape, strides, planes, self);
}

py::object channelView(const py::object& self, const std::string& name) {
    const ChannelValues* channel = self.cast<const PyField&>().field.channel(name);
    if (!channel) return py::none();
    const int width = channel->info().width;
    return channel->ints.empty() ? planarView(self, channel->floats.data(), width) : planarView(self, channel->ints.data(), width);
}

// A read-only view of a buffer that the sparse field `self` holds (no copy; keeps the field alive).
// Read-only: the lookups rely on the bricks' order and bounds, which writes could break.
template <class T>
py::array sparseView(const py::object& self, const T* data, std::vector<py::ssize_t> shape, std::vector<py::ssize_t> strides) {
    py::array view(py::dtype::of<T>(), std::move(shape), std::move(strides), data, self);
    view.attr("setflags")(py::arg("write") = false);
    return view;
}

// The module's notes (its methods, signs, devices and formats, from the registries), its version,
// and the error, warning and result types every call shares.
void registerModuleInfo(py::module_& m) {
#if SDFGEN_PYTHON_GPU
    gpu::registerDevices(); // first: the docstrings list them
#endif
    // The names the arguments take, from the library's registries.
    std::string fieldFormats, meshFormats;
    for (const FieldFormatInfo& format : knownFieldFormats()) {
        fieldFormats += (fieldFormats.empty() ? "" : ", ") + std::string(format.extension) + " (" + format.description + ")";
    }
    for (const std::string& extension : meshFormatExtensions()) meshFormats += (meshFormats.empty() ? "" : ", ") + extension;
    m.doc() = "sdfgen: exact signed distance fields, point queries and DeepSDF-style samples from triangle meshes\n\n"
              "Distance methods (bake's method): " + describeChoices(distanceMethodChoices()) + ".\n"
              "Sign methods (sign): " + describeChoices(signMethodChoices()) + "; point queries sign by " +
              namesOf(pointQuerySignChoices()) + ".\n"
              "Devices (bake's device): " + describeChoices(deviceChoices()) + ".\n"
              "Channels (bake's and sample's channels, besides sdf; CHANNELS): " + describeChannels() + ".\n"
              "Field formats: " + fieldFormats + ".\nMesh formats: " + meshFormats + " and the others Assimp reads.";
    const std::vector<Choice<SignMethod>> querySigns = pointQuerySignChoices();
    py::tuple querySignNames(querySigns.size());
    for (std::size_t i = 0; i < querySigns.size(); ++i) querySignNames[i] = querySigns[i].name;
    m.attr("_point_query_signs") = querySignNames; // for sdfgen.torch's messages
    py::tuple channelNames(channelInfos().size());
    for (std::size_t i = 0; i < channelInfos().size(); ++i) channelNames[i] = channelInfos()[i].name;
    m.attr("CHANNELS") = channelNames; // the channels bake and sample take besides sdf, in their order
    m.attr("__version__") = "0.1.0";
    static py::exception<Error> error(m, "Error", PyExc_RuntimeError);
    // Warnings from loads and bakes (what was skipped or is doubtful): warnings.warn with this
    // category, so that warnings.filterwarnings("error", category=sdfgen.Warning) turns them into errors.
    warningClass = PyErr_NewExceptionWithDoc("sdfgen.Warning", "What sdfgen skipped or doubts in a mesh or a bake", PyExc_UserWarning, nullptr);
    m.attr("Warning") = py::handle(warningClass);
    py::register_exception_translator([](std::exception_ptr p) {
        try {
            if (p) std::rethrow_exception(p);
        } catch (const Error& e) {
            error(e.what());
        }
    });

    closestHitClass = py::module_::import("collections").attr("namedtuple")(
        "ClosestHit", py::make_tuple("triangle", "point", "barycentric", "distance", "sign", "gradient"), py::arg("module") = "sdfgen")
                          .release();
    closestHitClass.attr("__doc__") = "What a query found at each point (Mesh.closest, sdfgen.torch.closest): triangle, point, barycentric, "
                                      "distance, sign, gradient";
    m.attr("ClosestHit") = closestHitClass;
}

// "Saves in the format ...": the docstring of both fields' save (pybind11 keeps its pointer).
const char* saveDoc() {
    static const std::string doc = [] {
        std::string extensions;
        for (const FieldFormatInfo& format : knownFieldFormats()) extensions += (extensions.empty() ? "" : ", ") + std::string(format.extension);
        return "Saves in the format the extension names (" + extensions + "), atomically";
    }();
    return doc.c_str();
}

// Mesh's point queries (numpy in, numpy out) and its normalization.
void addMeshQueries(py::class_<PyMesh>& mesh) {
    // pybind11 keeps a docstring's pointer: this lives as long as the module.
    const std::vector<Choice<SignMethod>> querySigns = pointQuerySignChoices();
    static const std::string signedDistanceDoc =
        "Signed distances (negative inside) at (..., 3) points, float32 of shape (...); sign: " + namesOf(querySigns);
    mesh
        .def(
            "signed_distance",
            [](const PyMesh& m, const py::array& points, const std::string& sign, int threads) {
                return query<float>(m, points, signFrom(sign), threads, &PointQueryOutputs::signedDistance, 1);
            },
            py::arg("points"), py::arg("sign") = "auto", py::arg("threads") = 0, signedDistanceDoc.c_str())
        .def(
            "unsigned_distance",
            [](const PyMesh& m, const py::array& points, int threads) {
                return query<float>(m, points, SignMethod::Auto, threads, &PointQueryOutputs::unsignedDistance, 1);
            },
            py::arg("points"), py::arg("threads") = 0, "Distances to the nearest triangle, float32 of shape (...)")
        .def(
            "closest_points",
            [](const PyMesh& m, const py::array& points, int threads) {
                return query<double>(m, points, SignMethod::Auto, threads, &PointQueryOutputs::closestPoint, 3);
            },
            py::arg("points"), py::arg("threads") = 0, "Nearest surface points, float64 of shape (..., 3)")
        .def(
            "nearest_triangle",
            [](const PyMesh& m, const py::array& points, int threads) {
                return query<std::int64_t>(m, points, SignMethod::Auto, threads, &PointQueryOutputs::triangle, 1);
            },
            py::arg("points"), py::arg("threads") = 0, "Index (into faces) of the nearest triangle, int64 of shape (...)")
        .def(
            "closest",
            [](const PyMesh& m, const py::array& input, const std::string& sign, int threads) {
                std::vector<py::ssize_t> shape;
                const auto points = pointsFrom(input, shape);
                const std::size_t count = std::size_t(points.size() / 3);
                std::vector<float> distance(count);
                std::vector<double> point(3 * count), barycentric(3 * count), gradient(3 * count);
                std::vector<std::int64_t> triangle(count);
                const double* data = points.data();
                const SignMethod method = signFrom(sign);
                runReleased(
                    [&](const RunControl& control) {
                        PointQueryOutputs out;
                        out.signedDistance = distance.data();
                        out.closestPoint = point.data();
                        out.barycentric = barycentric.data();
                        out.gradient = gradient.data();
                        out.triangle = triangle.data();
                        m.model->query(data, count, out, method, control);
                        return 0;
                    },
                    threads, py::none(), count);
                std::vector<std::int8_t> side(count);
                for (std::size_t i = 0; i < count; ++i) side[i] = std::signbit(distance[i]) ? -1 : 1;
                std::vector<py::ssize_t> vectors = shape;
                vectors.push_back(3);
                return closestHitClass(toNumpy(std::move(triangle), shape), toNumpy(std::move(point), vectors),
                                       toNumpy(std::move(barycentric), vectors), toNumpy(std::move(distance), shape),
                                       toNumpy(std::move(side), shape), toNumpy(std::move(gradient), vectors));
            },
            py::arg("points"), py::arg("sign") = "auto", py::arg("threads") = 0,
            "What a query finds at (..., 3) points, as an sdfgen.ClosestHit of arrays: triangle (int64 (...), into faces), point "
            "(float64 (..., 3), the closest surface point), barycentric (float64 (..., 3), point's weights on the triangle's "
            "corners faces[triangle]), distance (float32 (...), signed as signed_distance), sign (int8 (...), -1 inside, 1 "
            "outside, also on the surface) and gradient (float64 (..., 3), the signed distance's unit gradient; at distance 0 "
            "the triangle's face normal)")
        .def(
            "winding_number",
            [](const PyMesh& m, const py::array& points, int threads) {
                return query<double>(m, points, SignMethod::Auto, threads, &PointQueryOutputs::windingNumber, 1);
            },
            py::arg("points"), py::arg("threads") = 0, "Generalized winding numbers (exact), float64 of shape (...)")
        .def(
            "normalization",
            [](const PyMesh& m) {
                const NormalizedFrame frame = normalizedFrame(m.model->mesh());
                return py::make_tuple(tuple3(frame.centre), frame.radius);
            },
            "DeepSDF's normalization (centre, scale): normalized = (world - centre) / scale, with centre the bounding box's centre "
            "and scale 1.03 x the farthest vertex's distance from it (the mesh in the unit sphere with a 3% buffer); the units "
            "of sample()'s variances and of sample(normalize=True)");
}

// Mesh: built from arrays, a file or moved vertices; what it holds, its check, its queries, pickling.
void registerMesh(py::module_& m) {
    py::class_<PyMesh> mesh(m, "Mesh", "A triangle mesh with its distance tree, built once and kept for every query");
    mesh
        .def(py::init([](const py::array& vertices, const py::array& faces, const std::string& name, int threads) {
                 return meshFromArrays(vertices, faces, name, threads);
             }),
             py::arg("vertices"), py::arg("faces"), py::arg("name") = "<arrays>", py::arg("threads") = 0,
             "From (N, 3) float32 or float64 vertices and (M, 3) integer faces (counter-clockwise seen from outside)")
        .def_static(
            "load",
            [](const std::string& path, int threads) {
                PyMesh mesh;
                mesh.model = runReleased([&](const RunControl& control) { return std::make_shared<const Model>(Model::load(path, control)); },
                                         threads);
                return mesh;
            },
            py::arg("path"), py::arg("threads") = 0, "Loads a mesh file and builds its tree")
        .def(
            "with_vertices",
            [](const PyMesh& m, const py::array& vertices, int threads) {
                const Mesh& mesh = m.model->mesh();
                checkMovedVertices(mesh, vertices);
                return meshFromVertices(vertices, mesh.triangles, mesh.source, threads, m.model.get());
            },
            py::arg("vertices"), py::arg("threads") = 0,
            "The mesh with its vertices moved to (V, 3) new positions (float32 or float64), its faces kept: while the vertices "
            "group by position as before, the trees are refit, not built again, and the mesh check (auto's sign decision) is "
            "kept; otherwise it is built afresh. Queries equal those of a Mesh built from the new vertices")
        .def_property_readonly("source", [](const PyMesh& m) { return m.model->mesh().source; })
        .def_property_readonly("triangle_count", [](const PyMesh& m) { return m.model->mesh().triangleCount(); })
        .def_property_readonly("vertex_count", [](const PyMesh& m) { return m.model->mesh().positions.size(); })
        .def_property_readonly("dropped_degenerate", [](const PyMesh& m) { return m.model->mesh().droppedDegenerate; })
        .def_property_readonly("warnings", [](const PyMesh& m) { return m.model->mesh().warnings; })
        .def_property_readonly(
            "vertices",
            [](const PyMesh& m) {
                const Mesh& mesh = m.model->mesh();
                std::vector<double> world(3 * mesh.positions.size());
                for (std::size_t i = 0; i < mesh.positions.size(); ++i) {
                    const glm::dvec3 p = mesh.toWorld(glm::dvec3(mesh.positions[i]));
                    for (int a = 0; a < 3; ++a) world[3 * i + std::size_t(a)] = p[a];
                }
                return toNumpy(std::move(world), {py::ssize_t(mesh.positions.size()), 3});
            },
            "(N, 3) float64 world positions (a copy)")
        .def_property_readonly(
            "faces",
            [](const PyMesh& m) { return facesOf(m.model->mesh()); },
            "(M, 3) int64 triangles (zero-area ones dropped; the indices of nearest_triangle)")
        .def_property_readonly("bounds",
                               [](const PyMesh& m) {
                                   const WorldBounds b = m.model->mesh().worldBounds();
                                   return py::make_tuple(tuple3(b.min), tuple3(b.max));
                               },
                               "((xmin, ymin, zmin), (xmax, ymax, zmax)) in world coordinates")
        .def(
            "check",
            [](const PyMesh& m, int threads) {
                return checkToDict(runReleased([&](const RunControl& control) { return m.model->check(control); }, threads));
            },
            py::arg("threads") = 0, "The mesh check (holes, non-manifold edges and vertices, flipped faces, self-intersections) as a dict");
    addMeshQueries(mesh);
    mesh
        .def(py::pickle([](const PyMesh& m) { return meshState(m); }, [](const py::tuple& state) { return meshFromState(state); }))
        .def("__repr__", [](const PyMesh& m) {
            return "<sdfgen.Mesh " + m.model->mesh().source + ": " + std::to_string(m.model->mesh().triangleCount()) + " triangles>";
        });
}

// The nearest-point terms sdfgen.torch asks of one mesh's points (python/nearest.hpp), read from
// Python with the GIL held and measured on a worker: the outputs not wanted stay empty.
struct TorchTerms {
    // An output as the numpy array handed back (allocated, not zeroed: every element is written), or None.
    template <class T>
    struct Output {
        py::object array = py::none();
        T* data = nullptr;
    };
    template <class T>
    static Output<T> output(std::size_t count, py::ssize_t per) {
        const py::ssize_t n = py::ssize_t(count);
        py::array_t<T> values(per == 1 ? std::vector<py::ssize_t>{n} : std::vector<py::ssize_t>{n, per});
        return {values, values.mutable_data()};
    }

    const Model* model = nullptr;
    py::array_t<double, py::array::c_style> points;
    std::optional<py::array_t<double, py::array::c_style>> vertices;
    std::size_t count = 0;
    Output<double> distance, gradient, closest, weights, barycentric;
    Output<std::int64_t> corners, triangle;
    Output<std::int8_t> featureSize;

    NearestJob job() const {
        NearestTerms out;
        out.distance = distance.data;
        out.gradient = gradient.data;
        out.closest = closest.data;
        out.corners = corners.data;
        out.weights = weights.data;
        out.featureSize = featureSize.data;
        out.triangle = triangle.data;
        out.barycentric = barycentric.data;
        return {model, points.data(), count, vertices ? vertices->data() : nullptr, out};
    }

    // (distance, gradient, closest, corners, weights, feature_size, triangle, barycentric), None for those not wanted.
    py::tuple toPython() const {
        return py::make_tuple(distance.array, gradient.array, closest.array, corners.array, weights.array, featureSize.array,
                              triangle.array, barycentric.array);
    }
};

// Which terms sdfgen.torch wants (the keyword arguments of _nearest_terms).
struct TermsWanted {
    bool gradient = false, closest = false, features = false, hit = false;
};

TorchTerms torchTerms(const PyMesh& mesh, const py::array& points, const std::optional<py::array>& vertices, TermsWanted want) {
    TorchTerms terms;
    terms.model = mesh.model.get();
    std::vector<py::ssize_t> shape;
    terms.points = pointsFrom(points, shape);
    terms.count = std::size_t(terms.points.size() / 3);
    if (vertices) {
        const std::size_t vertexCount = mesh.model->mesh().positions.size();
        terms.vertices = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(*vertices);
        if (!*terms.vertices || terms.vertices->ndim() != 2 || terms.vertices->shape(1) != 3 ||
            std::size_t(terms.vertices->shape(0)) != vertexCount) {
            throw py::value_error("vertices must be the mesh's " + std::to_string(vertexCount) + " vertices, of shape (V, 3)");
        }
    }
    // Not wanted: None (for no points, an empty array all the same, as numpy gives it).
    auto wanted = [&terms](bool want, auto& out, py::ssize_t per) {
        if (want || terms.count == 0) out = TorchTerms::output<std::remove_pointer_t<decltype(out.data)>>(terms.count, per);
    };
    wanted(true, terms.distance, 1);
    wanted(want.gradient, terms.gradient, 3);
    wanted(want.closest, terms.closest, 3);
    wanted(want.features, terms.corners, 3);
    wanted(want.features, terms.weights, 3);
    wanted(want.features, terms.featureSize, 1);
    wanted(want.hit, terms.triangle, 1);
    wanted(want.hit, terms.barycentric, 3);
    return terms;
}

// Measures every mesh's terms in one call (measureNearestBatch: one pass over the thread pool).
py::list measureTorchTerms(std::vector<TorchTerms>& batch, const std::optional<std::string>& sign, int threads) {
    const std::optional<SignMethod> method = sign ? std::optional<SignMethod>(signFrom(*sign)) : std::nullopt;
    std::vector<NearestJob> jobs;
    std::size_t total = 0;
    for (TorchTerms& terms : batch) {
        jobs.push_back(terms.job());
        total += terms.count;
    }
    runReleased([&](const RunControl& control) {
        measureNearestBatch(jobs, method, control);
        return 0;
    }, threads, py::none(), total);
    py::list results;
    for (TorchTerms& terms : batch) results.append(terms.toPython());
    return results;
}

// For sdfgen.torch (python/sdfgen/torch.py): the nearest-point terms of its values and gradients,
// flat per point (python/nearest.hpp); None for those not asked for. `vertices` (V, 3): the
// full-precision coordinates the mesh was built from; no sign gives unsigned distances.
// _nearest_terms_batch: the same for lists of meshes, points and vertices (None for a mesh's own),
// a list of the tuples, measured in one pass.
void registerTorchTerms(py::module_& m) {
    m.def(
        "_nearest_terms",
        [](const PyMesh& mesh, const py::array& points, const std::optional<py::array>& vertices, const std::optional<std::string>& sign,
           bool gradient, bool closest, bool features, bool hit, int threads) {
            std::vector<TorchTerms> batch;
            batch.push_back(torchTerms(mesh, points, vertices, {gradient, closest, features, hit}));
            return py::tuple(measureTorchTerms(batch, sign, threads)[0]);
        },
        py::arg("mesh"), py::arg("points"), py::arg("vertices") = py::none(), py::arg("sign") = py::none(), py::arg("gradient") = false,
        py::arg("closest") = false, py::arg("features") = false, py::arg("hit") = false, py::arg("threads") = 0);
    m.def(
        "_nearest_terms_batch",
        [](const std::vector<py::object>& meshes, const std::vector<py::array>& points,
           const std::vector<std::optional<py::array>>& vertices, const std::optional<std::string>& sign, bool gradient, bool closest,
           bool features, bool hit, int threads) {
            if (points.size() != meshes.size() || vertices.size() != meshes.size()) {
                throw py::value_error("a batch takes one points array and one vertices array (or None) per mesh");
            }
            std::vector<TorchTerms> batch;
            for (std::size_t b = 0; b < meshes.size(); ++b) {
                batch.push_back(torchTerms(meshes[b].cast<const PyMesh&>(), points[b], vertices[b], {gradient, closest, features, hit}));
            }
            return measureTorchTerms(batch, sign, threads);
        },
        py::arg("meshes"), py::arg("points"), py::arg("vertices"), py::arg("sign") = py::none(), py::arg("gradient") = false,
        py::arg("closest") = false, py::arg("features") = false, py::arg("hit") = false, py::arg("threads") = 0);
    // The vertices' gradient in a backward pass of sdfgen.torch's distances, from the forward pass's
    // terms: (V, 3) float64 (scatterVertexGradient).
    m.def(
        "_vertex_gradient",
        [](const py::array_t<std::int64_t, py::array::c_style>& corners, const py::array_t<double, py::array::c_style>& weights,
           const py::array_t<double, py::array::c_style>& gradient, const py::array_t<double, py::array::c_style>& upstream,
           std::size_t vertexCount) {
            const std::size_t count = std::size_t(upstream.size());
            if (std::size_t(corners.size()) != 3 * count || std::size_t(weights.size()) != 3 * count || std::size_t(gradient.size()) != 3 * count) {
                throw py::value_error("corners, weights and gradient must have 3 values per upstream value");
            }
            std::vector<double> vertexGradient(3 * vertexCount, 0.0);
            scatterVertexGradient(corners.data(), weights.data(), gradient.data(), upstream.data(), count, vertexGradient.data(), vertexCount);
            return toNumpy(std::move(vertexGradient), {py::ssize_t(vertexCount), 3});
        },
        py::arg("corners"), py::arg("weights"), py::arg("gradient"), py::arg("upstream"), py::arg("vertex_count"));
    // A batch's meshes in one pass: vertices[b] moved from previous[b] (Mesh.with_vertices), or,
    // where previous[b] is None, a new mesh of vertices[b] and faces[b] (Mesh(vertices, faces)).
    m.def(
        "_meshes_batch",
        [](const std::vector<py::object>& previous, const std::vector<py::array>& vertices,
           const std::vector<std::optional<py::array>>& faces, const std::string& name, int threads) {
            if (vertices.size() != previous.size() || faces.size() != previous.size()) {
                throw py::value_error("a batch takes one previous mesh (or None), vertices and faces (or None) per mesh");
            }
            std::vector<MeshInput> inputs;
            for (std::size_t b = 0; b < previous.size(); ++b) {
                if (!previous[b].is_none()) {
                    const Model& model = *previous[b].cast<const PyMesh&>().model;
                    checkMovedVertices(model.mesh(), vertices[b]);
                    inputs.push_back(meshInput(vertices[b], model.mesh().triangles, model.mesh().source, &model));
                } else {
                    if (!faces[b]) throw py::value_error("a new mesh of a batch needs its faces");
                    checkVertexShape(vertices[b]);
                    checkReal(vertices[b], "vertices");
                    inputs.push_back(meshInput(vertices[b], trianglesFrom(*faces[b], vertices[b].shape(0), name), name, nullptr));
                }
            }
            const std::vector<std::shared_ptr<const Model>> models =
                runReleased([&](const RunControl& control) { return modelsOf(inputs, control); }, threads);
            py::list meshes;
            for (const std::shared_ptr<const Model>& model : models) meshes.append(PyMesh{model});
            return meshes;
        },
        py::arg("previous"), py::arg("vertices"), py::arg("faces"), py::arg("name") = "<arrays>", py::arg("threads") = 0);
}

// Field: a dense field's values and channels as numpy views, its sample positions, saving.
void registerField(py::module_& m) {
    py::class_<PyField> fieldClass(m, "Field", "A signed distance field on a grid of cubic voxels (samples at voxel centres)");
    addFieldInfo(fieldClass);
    // One view per channel of the registry, under its name.
    for (const ChannelInfo& info : channelInfos()) {
        const std::string name = info.name;
        const std::string shape = info.width > 1 ? "(nx, ny, nz, " + std::to_string(info.width) + ")" : "(nx, ny, nz)";
        static std::deque<std::string> docs; // pybind11 keeps a docstring's pointer
        docs.push_back(shape + (info.type == ChannelType::Int32 ? " int32" : " float32") + " view of the " + name + " channel: " +
                       info.description + "; None unless baked with channels including '" + name + "'");
        fieldClass.def_property_readonly(info.name, [name](const py::object& self) { return channelView(self, name); }, docs.back().c_str());
    }
    fieldClass
        .def_property_readonly("background", [](const PyField& f) { return f.field.background; },
                               "0 when every value is a distance; for a band field made dense (SparseField.to_dense), the "
                               "magnitude of the values outside the band, which tell only the side")
        .def_property_readonly(
            "values",
            [](py::object self) {
                PyField& f = self.cast<PyField&>();
                const glm::ivec3 d = f.field.grid.dims;
                const py::ssize_t item = sizeof(float);
                // values[i, j, k] is sample (i, j, k): the buffer is x fastest, so Fortran strides.
                return py::array_t<float>({py::ssize_t(d.x), py::ssize_t(d.y), py::ssize_t(d.z)},
                                          {item, item * d.x, item * d.x * d.y}, f.field.values.data(), self);
            },
            "(nx, ny, nz) float32 view of the field's values (no copy; keeps the field alive)")
        .def(
            "positions",
            [](const PyField& f) {
                const Grid& g = f.field.grid;
                std::vector<double> out(3 * g.sampleCount());
                std::size_t n = 0;
                for (int i = 0; i < g.dims.x; ++i) {
                    for (int j = 0; j < g.dims.y; ++j) {
                        for (int k = 0; k < g.dims.z; ++k) {
                            const glm::dvec3 p = g.position(i, j, k);
                            out[n++] = p.x;
                            out[n++] = p.y;
                            out[n++] = p.z;
                        }
                    }
                }
                return toNumpy(std::move(out), {g.dims.x, g.dims.y, g.dims.z, 3});
            },
            "(nx, ny, nz, 3) float64 world position of each value")
        .def(
            "save",
            [](const PyField& f, const std::string& path, double band) {
                SaveOptions options;
                options.band = band;
                py::gil_scoped_release release;
                saveField(f.field, path, options);
            },
            py::arg("path"), py::arg("band") = 0.0, saveDoc())
        .def("__repr__", [](const PyField& f) {
            const Grid& g = f.field.grid;
            return "<sdfgen.Field " + std::to_string(g.dims.x) + "x" + std::to_string(g.dims.y) + "x" + std::to_string(g.dims.z) +
                   " of " + f.field.source + ", " + f.field.method + " sign=" + f.field.parameter("sign") + ">";
        });
}

// SparseField: a narrow-band field's bricks as numpy views, lookups, saving and loading.
void registerSparseField(py::module_& m) {
    py::class_<PySparseField> sparseClass(
        m, "SparseField",
        "A narrow-band field (bake with band > 0, or a sparse .npz or .vdb file): exact distances within the band, in "
        "bricks of 8x8x8 samples; every other sample is +background outside the solid and -background inside");
    addFieldInfo(sparseClass);
    sparseClass
        .def_static(
            "load",
            [](const std::string& path) {
                py::gil_scoped_release release;
                return std::make_unique<PySparseField>(loadSparseField(path));
            },
            py::arg("path"),
            "Loads any field file as sparse: a sparse .npz or .vdb as it is, a dense file through its samples (bricks "
            "where a sample lies within the file's band of the surface, 3 voxels when it names none)")
        .def_property_readonly("background", [](const PySparseField& f) { return f.field.background(); },
                               "band * voxel_size: the magnitude of every sample outside the band")
        .def_property_readonly(
            "band",
            [](const PySparseField& f) {
                // The band as the bake was given it, else from the float background (in float, where
                // band * voxel was rounded: 3, not 3.0000001).
                const std::string given = f.field.parameter("band");
                char* end = nullptr;
                const double band = std::strtod(given.c_str(), &end);
                return !given.empty() && *end == '\0' && std::isfinite(band) ? band : double(f.field.background() / float(f.field.grid().voxel));
            },
            "The band's half-width in voxels")
        .def_property_readonly(
            "brick_origins",
            [](const py::object& self) {
                PySparseField& f = self.cast<PySparseField&>();
                if (f.brickOrigins.size() != 3 * f.field.bricks().size()) {
                    f.brickOrigins.resize(3 * f.field.bricks().size());
                    for (std::size_t b = 0; b < f.field.bricks().size(); ++b) {
                        for (int a = 0; a < 3; ++a) f.brickOrigins[3 * b + std::size_t(a)] = f.field.bricks()[b][a] * SparseField::kBrick;
                    }
                }
                const py::ssize_t item = sizeof(int);
                return sparseView(self, f.brickOrigins.data(), {py::ssize_t(f.field.bricks().size()), 3}, {3 * item, item});
            },
            "(B, 3) int32 read-only view: the first sample (i, j, k) of each brick, multiples of 8, ordered by k, then j, "
            "then i (made once, 12 bytes a brick)")
        .def_property_readonly(
            "brick_values",
            [](const py::object& self) {
                const SparseField& f = self.cast<const PySparseField&>().field;
                const py::ssize_t item = sizeof(float), n = SparseField::kBrick;
                // brick_values[a, b, c, n], as the sparse .npz stores it: x fastest, so Fortran order.
                return sparseView(self, f.values().data(), {n, n, n, py::ssize_t(f.bricks().size())}, {item, item * n, item * n * n, item * n * n * n});
            },
            "(8, 8, 8, B) float32 read-only view in Fortran order (no copy): brick_values[a, b, c, n] is sample "
            "brick_origins[n] + (a, b, c); samples past the grid's end hold +background")
        .def_property_readonly(
            "inside_boxes",
            [](const py::object& self) {
                const SparseField& f = self.cast<const PySparseField&>().field;
                const py::ssize_t item = sizeof(int);
                static_assert(sizeof(std::array<int, 6>) == 6 * sizeof(int), "boxes are packed int sextuples");
                return sparseView(self, reinterpret_cast<const int*>(f.insideBoxes().data()), {py::ssize_t(f.insideBoxes().size()), 6},
                                  {6 * item, item});
            },
            "(R, 6) int32 read-only view (no copy): i0 j0 k0 i1 j1 k1, the samples [i0, i1) x [j0, j1) x [k0, k1) outside "
            "every brick and inside the solid (-background); samples in neither a brick nor a box are outside (+background)")
        .def_property_readonly("active_count", [](const PySparseField& f) { return f.field.activeCount(); },
                               "The samples in the band (|value| < background), counted")
        .def(
            "at",
            [](const PySparseField& f, int i, int j, int k) {
                const glm::ivec3 d = f.field.grid().dims;
                if (i < 0 || j < 0 || k < 0 || i >= d.x || j >= d.y || k >= d.z) {
                    throw Error("sample (" + std::to_string(i) + ", " + std::to_string(j) + ", " + std::to_string(k) +
                                ") is outside the " + std::to_string(d.x) + "x" + std::to_string(d.y) + "x" + std::to_string(d.z) + " grid");
                }
                return f.field.at(i, j, k);
            },
            py::arg("i"), py::arg("j"), py::arg("k"), "The value of sample (i, j, k)")
        .def(
            "sample",
            [](const PySparseField& f, const py::array& input, int threads) {
                std::vector<py::ssize_t> shape;
                const auto points = pointsFrom(input, shape);
                const std::size_t count = std::size_t(points.size() / 3);
                std::vector<float> out(count);
                const double* data = points.data();
                // As Mesh's queries: a NaN would reach an undefined conversion to a sample index.
                for (std::size_t i = 0; i < 3 * count; ++i) {
                    if (!std::isfinite(data[i])) throw Error("query point " + std::to_string(i / 3) + " has a non-finite coordinate");
                }
                runReleased(
                    [&](const RunControl& control) {
                        constexpr std::size_t kBlock = 4096;
                        parallelFor((count + kBlock - 1) / kBlock, control, [&](std::size_t block) {
                            for (std::size_t n = block * kBlock, end = std::min(count, n + kBlock); n < end; ++n) {
                                out[n] = f.field.sample(glm::dvec3(data[3 * n], data[3 * n + 1], data[3 * n + 2]));
                            }
                        });
                        return 0;
                    },
                    threads, py::none(), count);
                return toNumpy(std::move(out), shape);
            },
            py::arg("points"), py::arg("threads") = 0,
            "Trilinear interpolation of the samples at (..., 3) world points (clamped to the grid), float32 of shape (...)")
        .def(
            "to_dense",
            [](const PySparseField& f) {
                auto result = std::make_unique<PyField>();
                py::gil_scoped_release release;
                result->field = f.field.toDense();
                return result;
            },
            "The dense Field (every sample; Field.background tells the band's values from the sides); sdfgen.Error when it "
            "does not fit in memory")
        .def(
            "save",
            [](const PySparseField& f, const std::string& path) {
                py::gil_scoped_release release;
                saveSparseField(f.field, path);
            },
            py::arg("path"),
            "Saves atomically: .vdb (a level set) and .npz keep it sparse; .sdf, .npy and .nrrd write the dense form, "
            "or raise sdfgen.Error when it does not fit in memory")
        .def("__repr__", [](const PySparseField& f) {
            const Grid& g = f.field.grid();
            return "<sdfgen.SparseField " + std::to_string(g.dims.x) + "x" + std::to_string(g.dims.y) + "x" + std::to_string(g.dims.z) +
                   " of " + f.field.source + ", " + std::to_string(f.field.bricks().size()) + " bricks, " + f.field.method +
                   " sign=" + f.field.parameter("sign") + ">";
        });
}

// bake (a Field, or a SparseField for a band) and load_field.
void registerBakeAndLoad(py::module_& m) {
    // pybind11 keeps a docstring's pointer: this lives as long as the module.
    static const std::string bakeDoc =
        "Bakes a field: res voxels along the padded box's longest side. progress(fraction) is called on this thread; "
        "Ctrl+C cancels. method: " + namesOf(distanceMethodChoices()) + "; sign: " + namesOf(signMethodChoices()) +
        " (see the module's notes). device: where exact distances and winding signs run: " + describeChoices(deviceChoices()) +
        ". channels: 'sdf' or a comma-separated list (or sequence) adding " + channelNames(", ", " and ", "") + " (method exact, "
        "on the CPU): " + channelNames(", .", ", .", "Field.") + ". band > 0: a narrow-band bake (method exact, on the CPU): exact "
        "distances only within band voxels of the surface, returned as a SparseField; the dense grid is never allocated. "
        "ValueError, before any work, for settings out of their limits (res and rays 1 to 65536, padding 0 to 100, band 0 or "
        "1 to 1e9) or that do not go together, as sdfgen bake refuses them.";
    m.def(
        "bake",
        [](const PyMesh& mesh, int res, double padding, const std::string& method, const std::string& sign, int threads,
           const py::object& progress, int rays, const std::string& device, const py::object& channels, double band) -> py::object {
            BakeSettings settings;
            settings.band = band;
            settings.channels = channelsFrom(channels);
            settings.device = choose(deviceChoices(), "device", device);
            settings.res = res;
            settings.padding = padding;
            settings.method = choose(distanceMethodChoices(), "method", method);
            settings.sign = signFrom(sign);
            settings.rays = rays;
            // Refused before any work, as by every front end (the keywords are the settings' names).
            if (const std::optional<SettingsProblem> refused = problem(settings)) throw py::value_error(refused->message);
            BakeResult baked = runReleased([&](const RunControl& control) { return mesh.model->bake(settings, control); }, threads, progress);
            AnyField field = std::move(baked.field);
            return fieldObject(std::move(field), std::move(baked));
        },
        py::arg("mesh"), py::arg("res") = 64, py::arg("padding") = 0.1, py::arg("method") = "exact", py::arg("sign") = "auto",
        py::arg("threads") = 0, py::arg("progress") = py::none(), py::arg("rays") = 64, py::arg("device") = "cpu",
        py::arg("channels") = "sdf", py::arg("band") = 0.0,
        bakeDoc.c_str());

    m.def(
        "load_field",
        [](const std::string& path) -> py::object {
            AnyField field;
            {
                py::gil_scoped_release release;
                field = loadAnyField(path);
            }
            return fieldObject(std::move(field), std::nullopt);
        },
        py::arg("path"),
        "Loads a field saved in any format sdfgen writes: a SparseField for a sparse file (a sparse .npz, a .vdb level set "
        "with inactive voxels), a Field otherwise (SparseField.load loads any file as sparse)");
}

// sample: DeepSDF-style training samples.
void registerSample(py::module_& m) {
    // pybind11 keeps a docstring's pointer: this lives as long as the module.
    static std::string sampleDoc =
        "DeepSDF-style samples: (points (n, 3) float32, sdf (n,) float32), in world units, or with normalize=True in DeepSDF's "
        "(Mesh.normalization(): (points - centre) / scale, sdf / scale; the mesh in the unit sphere). Defaults are DeepSDF's: "
        "47/50 near the surface (half with each variance, wide_variance then narrow_variance, in the normalized units; "
        "near_variance and far_variance are their old names), the rest uniform in the padded box. "
        "channels ('sdf' or a list adding " + channelNames(", ", ", ", "") + ") appends, in that order, each as (n, width) of its type "
        "(float32 or int32; (n,) for width 1; a point such as closest normalized too) to the tuple.";
    m.def(
        "sample",
        [](const PyMesh& mesh, std::size_t n, std::uint64_t seed, double surfaceFraction, double wideVariance, double narrowVariance,
           double padding, const std::string& sign, int threads, const py::object& channels, bool normalize,
           std::optional<double> nearVariance, std::optional<double> farVariance) {
            // The old names (near_variance was the wider scale, far_variance the narrower): still taken.
            for (const auto& [old, now] : {std::pair{"near_variance", "wide_variance"}, std::pair{"far_variance", "narrow_variance"}}) {
                if ((std::string(old) == "near_variance" ? nearVariance : farVariance).has_value()) {
                    const std::string message = std::string("sdfgen.sample: ") + old + " is now " + now + " (the same scale)";
                    if (PyErr_WarnEx(PyExc_DeprecationWarning, message.c_str(), 1) != 0) throw py::error_already_set();
                }
            }
            SampleSettings settings;
            settings.channels = channelsFrom(channels);
            settings.seed = seed;
            settings.surfaceFraction = surfaceFraction;
            settings.nearVariance = nearVariance.value_or(wideVariance);
            settings.farVariance = farVariance.value_or(narrowVariance);
            settings.padding = padding;
            settings.sign = signFrom(sign);
            Samples samples = runReleased([&](const RunControl& control) { return sampleSdf(*mesh.model, n, settings, control); }, threads, py::none(), n);
            if (normalize) {
                // DeepSDF's units: (world - centre) / radius, the distances / radius, from the world samples in double.
                const NormalizedFrame frame = normalizedFrame(mesh.model->mesh());
                auto toFrame = [&frame](std::vector<float>& xyz) {
                    for (std::size_t i = 0; i < xyz.size(); ++i) xyz[i] = float((double(xyz[i]) - frame.centre[int(i % 3)]) / frame.radius);
                };
                toFrame(samples.points);
                for (ChannelValues& channel : samples.channels) {
                    if (channel.info().vector == ChannelVector::Position) toFrame(channel.floats);
                }
                for (float& d : samples.sdf) d = float(double(d) / frame.radius);
            }
            py::list arrays;
            arrays.append(toNumpy(std::move(samples.points), {py::ssize_t(n), 3}));
            arrays.append(toNumpy(std::move(samples.sdf), {py::ssize_t(n)}));
            for (ChannelValues& channel : samples.channels) {
                const int width = channel.info().width;
                const std::vector<py::ssize_t> shape = width > 1 ? std::vector<py::ssize_t>{py::ssize_t(n), width} : std::vector<py::ssize_t>{py::ssize_t(n)};
                if (channel.ints.empty()) arrays.append(toNumpy(std::move(channel.floats), shape));
                else arrays.append(toNumpy(std::move(channel.ints), shape));
            }
            return py::tuple(arrays);
        },
        py::arg("mesh"), py::arg("n"), py::arg("seed") = 0, py::arg("surface_fraction") = 47.0 / 50.0, py::arg("wide_variance") = 0.0025,
        py::arg("narrow_variance") = 0.00025, py::arg("padding") = 0.1, py::arg("sign") = "auto", py::arg("threads") = 0,
        py::arg("channels") = "sdf", py::arg("normalize") = false, py::arg("near_variance") = py::none(), py::arg("far_variance") = py::none(),
        sampleDoc.c_str());
}

} // namespace

} // namespace sdfgen::python

using namespace sdfgen::python;

// The compiled part of the package sdfgen (python/sdfgen/__init__.py re-exports it).
PYBIND11_MODULE(_sdfgen, m) {
    registerModuleInfo(m);
    registerMesh(m);
    registerTorchTerms(m);
    registerField(m);
    registerSparseField(m);
    registerBakeAndLoad(m);
    registerSample(m);
}
