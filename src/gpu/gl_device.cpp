#include "gpu/gl_device.hpp"
#include "gpu/flat_bvh.hpp"
#include "render/egl_context.hpp"
#include "render/gl.hpp"
#include "render/shader.hpp"
#include "sdfgen/error.hpp"
#include "core/mesh/sample_positions.hpp"

#include <glm/common.hpp>
#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <mutex>

namespace sdfgen::gpu {

namespace {

// An SSBO that frees itself.
class Buffer {
public:
    Buffer() { glCreateBuffers(1, &id_); }
    ~Buffer() { glDeleteBuffers(1, &id_); }
    Buffer(const Buffer&) = delete;
    Buffer& operator=(const Buffer&) = delete;

    template <class T>
    void upload(const std::vector<T>& data) {
        glNamedBufferData(id_, GLsizeiptr(std::max<std::size_t>(data.size(), 1) * sizeof(T)), data.empty() ? nullptr : data.data(),
                          GL_STATIC_DRAW);
    }
    void allocate(std::size_t bytes) { glNamedBufferData(id_, GLsizeiptr(std::max<std::size_t>(bytes, 4)), nullptr, GL_DYNAMIC_COPY); }
    void clear() { glClearNamedBufferData(id_, GL_R32I, GL_RED_INTEGER, GL_INT, nullptr); }
    template <class T>
    void download(T* out, std::size_t count) const {
        glGetNamedBufferSubData(id_, 0, GLsizeiptr(count * sizeof(T)), out);
    }
    void bind(GLuint binding) const { glBindBufferBase(GL_SHADER_STORAGE_BUFFER, binding, id_); }

private:
    GLuint id_ = 0;
};

// Phase times of one device call, printed to stderr when SDFGEN_GPU_TIMES is set (bench/gpu.sh).
class PhaseTimes {
public:
    explicit PhaseTimes(const char* call) : call_(call), enabled_(std::getenv("SDFGEN_GPU_TIMES") != nullptr) {}
    ~PhaseTimes() {
        if (enabled_) std::fprintf(stderr, "gpu %s:%s\n", call_, text_.c_str());
    }
    // Closes the phase that ran since the last mark (the GPU's work is finished first).
    void note(const char* what, double seconds) {
        if (!enabled_) return;
        char part[64];
        std::snprintf(part, sizeof(part), " (%s %.4f s)", what, seconds);
        text_ += part;
    }
    void count(const char* what, std::size_t n) {
        if (!enabled_) return;
        text_ += " (" + std::to_string(n) + " " + what + ")";
    }
    void mark(const char* phase) {
        if (!enabled_) return;
        glFinish();
        const auto now = std::chrono::steady_clock::now();
        char part[64];
        std::snprintf(part, sizeof(part), " %s %.4f s", phase, std::chrono::duration<double>(now - last_).count());
        text_ += part;
        last_ = now;
    }

private:
    const char* call_;
    bool enabled_;
    std::string text_;
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

std::string glString(GLenum name) {
    const GLubyte* text = glGetString(name);
    return text ? reinterpret_cast<const char*>(text) : "?";
}

// Every output buffer of a slab stays under this (and under the driver's SSBO limit); a dispatch
// covers one layer of 4x4x4 bricks (nearest) or at most kMaxGroups work groups of 8x4 rows
// (winding): milliseconds on a GPU, far from any watchdog. Progress and cancel between dispatches.
constexpr std::size_t kSlabBytes = std::size_t(64) << 20;
constexpr std::size_t kMaxGroups = 16384;

class GlDevice final : public ComputeDevice {
public:
    GlDevice() : context_(render::createHeadlessContext({1, 1})) {
        description_ = "GL vendor " + glString(GL_VENDOR) + ", renderer " + glString(GL_RENDERER) + ", version " + glString(GL_VERSION) +
                       " through " + context_->kind();
        renderer_ = glString(GL_RENDERER);
        hardware_ = !isSoftwareRenderer(renderer_);
        GLint64 limit = 0;
        glGetInteger64v(GL_MAX_SHADER_STORAGE_BLOCK_SIZE, &limit);
        maxBlockBytes_ = std::size_t(limit);
        slabBytes_ = std::min(kSlabBytes, maxBlockBytes_);
        // Test hook: a small budget makes small grids stream in many slabs.
        if (const char* bytes = std::getenv("SDFGEN_GPU_SLAB_BYTES"); bytes && std::atoll(bytes) > 0) {
            slabBytes_ = std::min(slabBytes_, std::size_t(std::atoll(bytes)));
        }
        context_->release();
    }
    ~GlDevice() override {
        context_->makeCurrent();
        nearest_.reset();
        nearestSigned_.reset();
        windingRows_.reset();
        windingPrefix_.reset();
        windingCaps_.reset();
    }

    std::string description() const override { return description_; }
    std::string renderer() const override { return renderer_; }
    bool hardware() const override { return hardware_; }

    void nearest(const Mesh& mesh, const Grid& grid, const PseudonormalSign* sign, const RunControl& control,
                 std::vector<float>& distance) override {
        Session session(*this);
        PhaseTimes times("nearest");
        const FlatBvh tree(mesh);
        times.mark("tree");
        checkFits(tree.triangles.size() * sizeof(FlatBvh::Triangle), "the mesh's triangles");
        Buffer nodes, triangles, samples, exactSamples, seeds, distances, pseudonormals;
        nodes.upload(tree.nodes);
        triangles.upload(tree.triangles);
        {
            std::vector<double> flat; // none when unsigned: the buffer still needs a store to be bound
            if (sign) {
                checkFits(sign->normals.size() * sizeof(glm::dvec3), "the mesh's pseudonormals");
                flat.reserve(3 * sign->normals.size());
                for (const glm::dvec3& n : sign->normals) flat.insert(flat.end(), {n.x, n.y, n.z});
            }
            pseudonormals.upload(flat);
        }
        const std::vector<double> coordinates = sampleAxes(mesh, grid);
        samples.upload(rounded(coordinates));
        exactSamples.upload(coordinates);
        const glm::ivec3 dims = grid.dims, bricks = (dims + 3) / 4;
        const std::size_t layerSamples = std::size_t(dims.x) * std::size_t(dims.y);
        const int slabLayers = this->slabLayers(layerSamples * sizeof(float), 4, dims.z);
        seeds.allocate(std::size_t(bricks.x) * std::size_t(bricks.y) * sizeof(std::uint32_t)); // one layer of bricks
        distances.allocate(layerSamples * std::size_t(slabLayers) * sizeof(float));
        nodes.bind(0);
        triangles.bind(1);
        samples.bind(2);
        seeds.bind(3);
        distances.bind(4);
        pseudonormals.bind(5);
        exactSamples.bind(6);
        distance.resize(grid.sampleCount());
        const render::Program& program = sign ? compiled(nearestSigned_, "nearest_signed.comp") : compiled(nearest_, "nearest.comp");
        times.mark("upload+compile");
        double downloadSeconds = 0;
        program.use();
        glProgramUniform3i(program.id(), glGetUniformLocation(program.id(), "dims"), dims.x, dims.y, dims.z);
        glProgramUniform1d(program.id(), glGetUniformLocation(program.id(), "unit"), mesh.unit);
        glProgramUniform1i(program.id(), glGetUniformLocation(program.id(), "flipped"), sign && sign->flipped ? 1 : 0);
        const glm::vec3 lo(tree.nodes[0].lo), hi(tree.nodes[0].hi);
        const glm::vec3 magnitude = glm::max(glm::abs(lo), glm::abs(hi));
        glProgramUniform1f(program.id(), glGetUniformLocation(program.id(), "meshMagnitude"),
                           std::max({magnitude.x, magnitude.y, magnitude.z}));
        const GLint slabZ = glGetUniformLocation(program.id(), "slabZ"), firstBrickZ = glGetUniformLocation(program.id(), "firstBrickZ");
        const GLint seedPass = glGetUniformLocation(program.id(), "seedPass");
        for (int z0 = 0; z0 < dims.z; z0 += slabLayers) {
            const int z1 = std::min(dims.z, z0 + slabLayers);
            glUniform1i(slabZ, z0);
            // One layer of bricks per dispatch: seeds, then the samples.
            for (int bz = z0 / 4; bz * 4 < z1; ++bz) {
                checkCancel(control);
                glUniform1i(firstBrickZ, bz);
                glUniform1i(seedPass, 1);
                glDispatchCompute(GLuint((bricks.x + 63) / 64), GLuint(bricks.y), 1);
                glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
                glUniform1i(seedPass, 0);
                glDispatchCompute(GLuint(bricks.x), GLuint(bricks.y), 1);
                glFinish();
                report(control, double(std::min(z1, bz * 4 + 4)) / dims.z);
            }
            glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
            const auto downloadStart = std::chrono::steady_clock::now();
            const std::size_t offset = std::size_t(z0) * layerSamples, count = std::size_t(z1 - z0) * layerSamples;
            distances.download(distance.data() + offset, count);
            downloadSeconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - downloadStart).count();
        }
        checkErrors("the distance pass");
        times.mark("dispatch+download");
        if (downloadSeconds > 0) times.note("of which download", downloadSeconds);
        if (sign) {
            const auto undecided = std::count_if(distance.begin(), distance.end(), [](float d) { return std::isnan(d); });
            times.count("samples left to the CPU", std::size_t(undecided));
        }
    }

    std::vector<std::int32_t> windingNumbers(const Mesh& mesh, const std::vector<glm::dvec3>& corners, const std::vector<std::int32_t>& weights,
                                             const WindingFans* fans, const Grid& grid, const RunControl& control,
                                             std::vector<std::uint8_t>& sides) override {
        Session session(*this);
        PhaseTimes times("winding");
        const glm::ivec3 dims = grid.dims;
        const std::size_t triangleCount = corners.size() / 3;
        checkFits(corners.size() * sizeof(glm::dvec3), "the closed surface's triangles");
        if (weights.size() != triangleCount) throw Error("GPU: one winding weight per triangle expected");
        Buffer cornerBuffer, weightBuffer, tiles, exactSamples, counts, winding;
        weightBuffer.upload(weights);
        {
            std::vector<double> flat(corners.size() * 3);
            for (std::size_t i = 0; i < corners.size(); ++i) {
                for (int c = 0; c < 3; ++c) flat[3 * i + std::size_t(c)] = corners[i][c];
            }
            cornerBuffer.upload(flat);
        }
        exactSamples.upload(sampleAxes(mesh, grid));
        const std::size_t rowLength = std::size_t(dims.x) + 1;
        // The suffix sums run one invocation per row, 64 to a work group, in one dispatch per slab:
        // a slab has at most 65535 x 64 rows (the smallest work group count GL allows).
        const int maxLayers = std::max(1, int(std::size_t(65535 * 64) / std::size_t(dims.y)));
        const int slabLayers = std::min(maxLayers, this->slabLayers(rowLength * std::size_t(dims.y) * sizeof(std::int32_t), 1, dims.z));
        counts.allocate(rowLength * std::size_t(dims.y) * std::size_t(slabLayers) * sizeof(std::int32_t));
        winding.allocate(std::size_t(dims.x) * std::size_t(dims.y) * std::size_t(slabLayers) * sizeof(std::int32_t));
        // The holes' fans for the fractional part (winding_caps.comp).
        Buffer fanNodes, fanLinks, fanList, fanPoints, sideBuffer;
        if (fans) {
            std::vector<double> nodeData;
            std::vector<glm::uvec2> links;
            for (const WindingFans::Node& n : fans->nodes) {
                nodeData.insert(nodeData.end(), {n.lo.x, n.lo.y, n.lo.z, n.hi.x, n.hi.y, n.hi.z, n.area, 0.0});
                links.push_back({n.first, n.leaf ? 1u : 0u});
            }
            std::vector<glm::ivec4> list;
            for (const WindingFans::Fan& fan : fans->fans) list.push_back({int(fan.first), int(fan.count), fan.weight, 0});
            std::vector<double> points;
            for (const glm::dvec3& p : fans->points) points.insert(points.end(), {p.x, p.y, p.z});
            checkFits(std::max(points.size(), nodeData.size()) * sizeof(double), "the holes' fans");
            fanNodes.upload(nodeData);
            fanLinks.upload(links);
            fanList.upload(list);
            fanPoints.upload(points);
            sideBuffer.allocate(std::size_t(dims.x) * std::size_t(dims.y) * std::size_t(slabLayers) * sizeof(std::int32_t));
            fanNodes.bind(7);
            fanLinks.bind(8);
            fanList.bind(9);
            fanPoints.bind(10);
            sideBuffer.bind(11);
            sides.resize(grid.sampleCount());
        }
        std::vector<std::int32_t> slabSides;
        cornerBuffer.bind(0);
        tiles.bind(1);
        counts.bind(3);
        winding.bind(4);
        weightBuffer.bind(5);
        exactSamples.bind(6);

        // Candidate rows per triangle, exactly as src/core/sign/winding_sign.cpp bounds them (a superset: the
        // exact test decides), cut into 8x4 tiles.
        struct Rows {
            int j0, j1, k0, k1;
        };
        std::vector<Rows> rows(triangleCount);
        const glm::dvec3 first = localPosition(mesh, grid, 0, 0, 0);
        const double h = grid.voxel / mesh.unit;
        for (std::size_t t = 0; t < triangleCount; ++t) {
            const glm::dvec3 &a = corners[3 * t], &b = corners[3 * t + 1], &c = corners[3 * t + 2];
            const double ylo = std::min({a.y, b.y, c.y}), yhi = std::max({a.y, b.y, c.y});
            const double zlo = std::min({a.z, b.z, c.z}), zhi = std::max({a.z, b.z, c.z});
            rows[t] = {std::max(0, int(std::floor((ylo - first.y) / h)) - 1), std::min(dims.y - 1, int(std::ceil((yhi - first.y) / h)) + 1),
                       std::max(0, int(std::floor((zlo - first.z) / h)) - 1), std::min(dims.z - 1, int(std::ceil((zhi - first.z) / h)) + 1)};
        }

        std::vector<std::int32_t> out(grid.sampleCount());
        const render::Program& rowsProgram = compiled(windingRows_, "winding_rows.comp");
        const render::Program& prefixProgram = compiled(windingPrefix_, "winding_prefix.comp");
        const render::Program* capsProgram = fans ? &compiled(windingCaps_, "winding_caps.comp") : nullptr;
        if (capsProgram) glProgramUniform3i(capsProgram->id(), glGetUniformLocation(capsProgram->id(), "dims"), dims.x, dims.y, dims.z);
        times.mark("upload+rows+compile");
        for (const render::Program* p : {&rowsProgram, &prefixProgram}) {
            glProgramUniform3i(p->id(), glGetUniformLocation(p->id(), "dims"), dims.x, dims.y, dims.z);
        }
        const int slabCount = (dims.z + slabLayers - 1) / slabLayers;
        for (int z0 = 0; z0 < dims.z; z0 += slabLayers) {
            const int z1 = std::min(dims.z, z0 + slabLayers);
            std::vector<glm::uvec4> work;
            for (std::size_t t = 0; t < triangleCount; ++t) {
                const Rows& r = rows[t];
                const int k0 = std::max(r.k0, z0), k1 = std::min(r.k1, z1 - 1);
                if (k0 > k1 || r.j0 > r.j1) continue;
                const std::uint32_t last = std::uint32_t(r.j1) | (std::uint32_t(k1) << 16);
                for (int k = k0; k <= k1; k += 4) {
                    for (int j = r.j0; j <= r.j1; j += 8) work.push_back({std::uint32_t(t), std::uint32_t(j), std::uint32_t(k), last});
                }
            }
            checkFits(work.size() * sizeof(glm::uvec4), "the crossing tiles of one slab");
            tiles.upload(work);
            counts.clear();
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
            rowsProgram.use();
            glUniform1i(glGetUniformLocation(rowsProgram.id(), "slabZ"), z0);
            const GLint firstTile = glGetUniformLocation(rowsProgram.id(), "firstTile");
            for (std::size_t start = 0; start < work.size(); start += kMaxGroups) {
                checkCancel(control);
                glUniform1i(firstTile, GLint(start));
                glDispatchCompute(GLuint(std::min(kMaxGroups, work.size() - start)), 1, 1);
                glFinish();
                // The slab's crossings are most of its work; its suffix sums and download the rest.
                const double slabDone = std::min(1.0, double(start + kMaxGroups) / double(work.size()));
                report(control, (double(z0 / slabLayers) + 0.9 * slabDone) / slabCount);
            }
            glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
            prefixProgram.use();
            const int slabRows = dims.y * (z1 - z0);
            glUniform1i(glGetUniformLocation(prefixProgram.id(), "rows"), slabRows);
            glDispatchCompute(GLuint((slabRows + 63) / 64), 1, 1);
            glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
            const std::size_t layerSamples = std::size_t(dims.x) * std::size_t(dims.y);
            winding.download(out.data() + std::size_t(z0) * layerSamples, std::size_t(z1 - z0) * layerSamples);
            if (capsProgram) {
                // One invocation per sample, 64 to a work group, at most kMaxGroups groups a dispatch.
                glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
                capsProgram->use();
                const int slabSamples = int(std::size_t(z1 - z0) * layerSamples);
                glUniform1i(glGetUniformLocation(capsProgram->id(), "slabZ"), z0);
                glUniform1i(glGetUniformLocation(capsProgram->id(), "slabSamples"), slabSamples);
                const GLint firstSample = glGetUniformLocation(capsProgram->id(), "firstSample");
                for (int first = 0; first < slabSamples; first += int(kMaxGroups) * 64) {
                    checkCancel(control);
                    glUniform1i(firstSample, first);
                    glDispatchCompute(GLuint(std::min<std::size_t>(kMaxGroups, (std::size_t(slabSamples - first) + 63) / 64)), 1, 1);
                    glFinish();
                }
                glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
                slabSides.resize(std::size_t(slabSamples));
                sideBuffer.download(slabSides.data(), slabSides.size());
                std::copy(slabSides.begin(), slabSides.end(), sides.begin() + std::ptrdiff_t(std::size_t(z0) * layerSamples));
            }
            report(control, double(z0 / slabLayers + 1) / slabCount);
        }
        checkErrors("the winding pass");
        times.mark("tiles+dispatch+download");
        if (fans) times.count("samples left to the CPU", std::size_t(std::count(sides.begin(), sides.end(), std::uint8_t(2))));
        return out;
    }

private:
    // Makes the context current on the calling thread for one call (the viewer bakes on a worker
    // thread), with the GL entry points loaded for it, and releases it afterwards.
    class Session {
    public:
        explicit Session(GlDevice& device) : device_(device), lock_(device.mutex_) {
            device_.context_->makeCurrent();
        }
        ~Session() { device_.context_->release(); }

    private:
        GlDevice& device_;
        std::lock_guard<std::mutex> lock_;
    };

    // Programs are compiled on first use: opening the device only to ask what it is (auto, info) stays cheap.
    static const render::Program& compiled(std::unique_ptr<render::Program>& program, const char* file) {
        if (!program) program = std::make_unique<render::Program>(file);
        return *program;
    }

    // sampleAxes rounded to float, as the CPU rounds them for its float search.
    static std::vector<float> rounded(const std::vector<double>& coordinates) {
        return std::vector<float>(coordinates.begin(), coordinates.end());
    }

    // Layers per slab so that a slab's buffer stays under slabBytes_: a multiple of `multiple`, at
    // least one multiple, and no more than the grid's `layers` need.
    int slabLayers(std::size_t layerBytes, int multiple, int gridLayers) const {
        const std::size_t budget = slabBytes_;
        const std::size_t layers = budget / std::max<std::size_t>(layerBytes, 1) / std::size_t(multiple) * std::size_t(multiple);
        if (layers == 0) {
            throw Error("the grid's layers are too large for the GPU (" + std::to_string(layerBytes * std::size_t(multiple) >> 20) +
                        " MiB for " + std::to_string(multiple) + ", the limit is " + std::to_string(budget >> 20) + " MiB); bake on device cpu instead");
        }
        const std::size_t needed = (std::size_t(gridLayers) + std::size_t(multiple) - 1) / std::size_t(multiple) * std::size_t(multiple);
        return int(std::min(layers, needed));
    }

    void checkFits(std::size_t bytes, const char* what) const {
        if (bytes > maxBlockBytes_) {
            throw Error(std::string(what) + " need " + std::to_string(bytes >> 20) + " MiB, more than the GPU's storage buffer limit of " +
                        std::to_string(maxBlockBytes_ >> 20) + " MiB; bake on device cpu instead");
        }
    }

    // A driver error (out of GPU memory, a limit passed) would leave the buffers undefined: never a
    // silently wrong field.
    static void checkErrors(const char* pass) {
        const GLenum error = glGetError();
        if (error == GL_NO_ERROR) return;
        while (glGetError() != GL_NO_ERROR) continue; // the rest of the queue, so the next call starts clean
        const char* name = error == GL_OUT_OF_MEMORY ? "out of GPU memory" : error == GL_INVALID_VALUE ? "a value beyond the driver's limits"
                                                                                                       : "an OpenGL error";
        throw Error(std::string("GPU: ") + pass + " failed (" + name + ", code " + std::to_string(error) + "); bake on device cpu instead");
    }

    static void checkCancel(const RunControl& control) {
        if (control.cancel && control.cancel->load()) throw Cancelled();
    }
    static void report(const RunControl& control, double fraction) {
        if (control.progress) control.progress(fraction);
    }

    std::mutex mutex_;
    std::unique_ptr<render::GlContext> context_;
    std::string description_;
    std::string renderer_;
    bool hardware_ = false;
    std::size_t maxBlockBytes_ = 0;
    std::size_t slabBytes_ = 0; // kSlabBytes, or less for the driver's limit or the test hook
    std::unique_ptr<render::Program> nearest_, nearestSigned_, windingRows_, windingPrefix_, windingCaps_;
};

} // namespace

bool isSoftwareRenderer(const std::string& renderer) {
    std::string lower = renderer;
    std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    for (const char* name : {"llvmpipe", "softpipe", "swrast", "software rasterizer", "swiftshader"}) {
        if (lower.find(name) != std::string::npos) return true;
    }
    return false;
}

std::unique_ptr<ComputeDevice> openGlDevice() { return std::make_unique<GlDevice>(); }

ComputeDevicePlugin glDevicePlugin() {
    ComputeDevicePlugin plugin;
    plugin.name = "gpu";
    plugin.description = "OpenGL 4.5 compute, on Mesa's llvmpipe too; an error when it cannot start";
    plugin.driver = "OpenGL 4.5 driver";
    plugin.mayBeHardware = render::eglMayHaveHardwareDevice;
    plugin.open = openGlDevice;
    return plugin;
}

} // namespace sdfgen::gpu
