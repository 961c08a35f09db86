// `sdfgen query`: exact point queries from the command line, NumPy arrays in and out.
#include "cli/commands.hpp"
#include "core/io/atomic_file.hpp"
#include "core/io/formats/format.hpp"
#include "core/io/formats/npy.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/model.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <memory>

namespace sdfgen::cli {

namespace {

struct QueryArgs {
    std::string mesh, points, output, what = "signed";
    SignMethod sign = SignMethod::Auto;
    int threads = 0;
};

// An (N, 3) float32 or float64 array, C or Fortran order, as x y z interleaved doubles.
std::vector<double> readPoints(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot open file (" + std::strerror(errno) + ")");
    in.seekg(0, std::ios::end);
    const std::uint64_t fileBytes = std::uint64_t(in.tellg());
    in.seekg(0);
    const formats::ReadBytes read = [&](void* data, std::size_t size) {
        in.read(static_cast<char*>(data), std::streamsize(size));
        return std::size_t(in.gcount());
    };
    const formats::NpyHeader header = formats::readNpyHeader(read, path);
    if (header.descr != "<f4" && header.descr != "<f8") {
        throw Error(path + ": points must be float32 or float64 (dtype '" + printable(header.descr) + "')");
    }
    if (header.shape.size() != 2 || header.shape[1] != 3) throw Error(path + ": points must be an (N, 3) array");
    const std::uint64_t n = header.shape[0];
    const std::size_t item = header.itemSize();
    const std::uint64_t declared = header.dataBytes(path); // Error when it overflows
    if (fileBytes - header.headerBytes != declared) {
        throw Error(path + ": the file holds " + std::to_string(fileBytes - header.headerBytes) + " bytes of data, not the " +
                    std::to_string(declared) + " its header declares");
    }
    std::vector<char> raw(n * 3 * item);
    if (read(raw.data(), raw.size()) != raw.size()) throw Error(path + ": read error");
    std::vector<double> points(3 * n);
    for (std::uint64_t i = 0; i < n; ++i) {
        for (std::uint64_t a = 0; a < 3; ++a) {
            const std::uint64_t at = header.fortranOrder ? a * n + i : 3 * i + a;
            if (item == 4) {
                float v;
                std::memcpy(&v, raw.data() + at * 4, 4);
                points[3 * i + a] = v;
            } else {
                std::memcpy(&points[3 * i + a], raw.data() + at * 8, 8);
            }
        }
    }
    return points;
}

template <class T>
void writeArray(const std::string& path, const std::string& descr, const std::vector<std::uint64_t>& shape, const std::vector<T>& values) {
    writeFileAtomically(path, [&](std::ostream& out) {
        const std::string header = formats::npyHeader(descr, false, shape);
        out.write(header.data(), std::streamsize(header.size()));
        out.write(reinterpret_cast<const char*>(values.data()), std::streamsize(values.size() * sizeof(T)));
    });
}

void runQuery(const QueryArgs& args) {
    refuseOverwritingInput(args.output, {args.mesh, args.points});
    const std::vector<double> points = readPoints(args.points);
    const std::size_t n = points.size() / 3;
    const RunControl control = commandControl(args.threads);
    const Model model = Model::load(args.mesh, control);
    PointQueryOutputs out;
    if (args.what == "signed" || args.what == "unsigned") {
        std::vector<float> values(n);
        (args.what == "signed" ? out.signedDistance : out.unsignedDistance) = values.data();
        model.query(points.data(), n, out, args.sign, control);
        writeArray(args.output, "<f4", {n}, values);
    } else if (args.what == "closest") {
        std::vector<double> values(3 * n);
        out.closestPoint = values.data();
        model.query(points.data(), n, out, args.sign, control);
        writeArray(args.output, "<f8", {n, 3}, values);
    } else if (args.what == "triangle") {
        std::vector<std::int64_t> values(n);
        out.triangle = values.data();
        model.query(points.data(), n, out, args.sign, control);
        writeArray(args.output, "<i8", {n}, values);
    } else {
        std::vector<double> values(n);
        out.windingNumber = values.data();
        model.query(points.data(), n, out, args.sign, control);
        writeArray(args.output, "<f8", {n}, values);
    }
    std::printf("%s: %zu points -> %s (%s)\n", args.mesh.c_str(), n, args.output.c_str(), args.what.c_str());
}

} // namespace

void addQueryCommand(CLI::App& app) {
    auto args = std::make_shared<QueryArgs>();
    CLI::App* query = app.add_subcommand("query", "Exact distances (or closest points, triangles, winding numbers) at points from a .npy file");
    query->add_option("mesh", args->mesh, "Input mesh (" + meshFormatList() + ", ...)")->required();
    query->add_option("points", args->points, "Points: an (N, 3) float32 or float64 .npy array")->required();
    query->add_option("-o,--output", args->output, "Output .npy: (N,) float32 distances, (N, 3) float64 closest points, (N,) int64 triangles or (N,) float64 winding numbers")->required();
    query->add_option("--what", args->what, "signed (default), unsigned, closest, triangle or winding")
        ->check(CLI::IsMember({"signed", "unsigned", "closest", "triangle", "winding"}));
    query->add_option("--sign", args->sign, "Sign of signed distances: " + describeChoices(pointQuerySignChoices()))
        ->transform(choiceOf(pointQuerySignChoices(), "point query sign"))
        ->default_str(toString(args->sign));
    addThreadsOption(*query, args->threads);
    query->footer("At a baked field's sample positions the signed distances equal the field's values exactly.");
    query->callback([args] { runQuery(*args); });
}

} // namespace sdfgen::cli
