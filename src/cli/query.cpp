// `sdfgen query`: exact point queries from the command line, NumPy arrays in and out.
#include "cli/commands.hpp"
#include "sdfgen/formats.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/model.hpp"

#include <cstdio>

namespace sdfgen::cli {

namespace {

struct QueryArgs {
    std::string mesh, points, output, what = "signed";
    SignMethod sign = SignMethod::Auto;
    int threads = 0;
};

void runQuery(const QueryArgs& args) {
    refuseOverwritingInput(args.output, {args.mesh, args.points});
    const std::vector<double> points = loadPointsNpy(args.points);
    const std::size_t n = points.size() / 3;
    const RunControl control = commandControl(args.threads);
    const Model model = Model::load(args.mesh, control);
    PointQueryOutputs out;
    if (args.what == "signed" || args.what == "unsigned") {
        std::vector<float> values(n);
        (args.what == "signed" ? out.signedDistance : out.unsignedDistance) = values.data();
        model.query(points.data(), n, out, args.sign, control);
        saveNpy(args.output, values, {n});
    } else if (args.what == "closest") {
        std::vector<double> values(3 * n);
        out.closestPoint = values.data();
        model.query(points.data(), n, out, args.sign, control);
        saveNpy(args.output, values, {n, 3});
    } else if (args.what == "triangle") {
        std::vector<std::int64_t> values(n);
        out.triangle = values.data();
        model.query(points.data(), n, out, args.sign, control);
        saveNpy(args.output, values, {n});
    } else {
        std::vector<double> values(n);
        out.windingNumber = values.data();
        model.query(points.data(), n, out, args.sign, control);
        saveNpy(args.output, values, {n});
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
