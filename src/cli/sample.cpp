// `sdfgen sample`: DeepSDF-style training samples (points near the surface and their signed distances).
#include "cli/commands.hpp"
#include "cli/progress.hpp"
#include "sdfgen/model.hpp"
#include "sdfgen/sample.hpp"

#include <cstdio>
#include <memory>

namespace sdfgen::cli {

namespace {

struct SampleArgs {
    std::string mesh;
    std::string output;
    std::size_t count = 0;
    SampleSettings settings;
    std::string channels = "sdf";
    int threads = 0;
};

void runSample(SampleArgs args) {
    Stopwatch clock;
    refuseOverwritingInput(args.output, {args.mesh});
    checkSamplesPath(args.output);
    RunControl control = commandControl(args.threads);
    args.settings.channels = parseChannels(args.channels);
    const Model model = Model::load(args.mesh, control);
    Samples samples;
    {
        ProgressBar bar;
        control.progress = bar.callback();
        samples = sampleSdf(model, args.count, args.settings, control);
    }
    saveSamples(samples, args.output);
    const SampleCounts counts = sampleCounts(args.count, args.settings);
    const double seconds = clock.seconds();
    std::printf("%s -> %s: %zu samples (%zu near, %zu far, %zu uniform), seed %llu, %.3f s, %.0f samples/s\n", args.mesh.c_str(),
                args.output.c_str(), samples.size(), counts.nearSurface, counts.farSurface, counts.uniform,
                static_cast<unsigned long long>(args.settings.seed), seconds, double(samples.size()) / seconds);
}

} // namespace

void addSampleOptions(CLI::App& command, SampleSettings& settings) {
    command.add_option("--seed", settings.seed, "Random seed: the same seed gives the same samples, whatever the thread count")
        ->check(wholeNumber(0, UINT64_MAX))
        ->capture_default_str();
    command.add_option("--surface-fraction", settings.surfaceFraction, "Share of samples near the surface (DeepSDF: 47/50); the rest are uniform in the padded box")
        ->check(finiteRange(0.0, 1.0))
        ->capture_default_str();
    command.add_option("--wide-variance", settings.nearVariance,
                       "Variance of the wider noise scale (DeepSDF's variance), in DeepSDF's normalized units (unit sphere)")
        ->check(finiteRange(0.0, 1e6))
        ->capture_default_str();
    command.add_option("--narrow-variance", settings.farVariance,
                       "Variance of the narrower noise scale (DeepSDF's second_variance), in the same units")
        ->check(finiteRange(0.0, 1e6))
        ->capture_default_str();
    // Their earlier names (the "far" scale was the narrower one), still taken.
    command.add_option("--near-variance", settings.nearVariance, "The old name of --wide-variance")->check(finiteRange(0.0, 1e6));
    command.add_option("--far-variance", settings.farVariance, "The old name of --narrow-variance")->check(finiteRange(0.0, 1e6));
}

void addSampleCommand(CLI::App& app) {
    auto args = std::make_shared<SampleArgs>();
    CLI::App* sample = app.add_subcommand("sample", "Draw DeepSDF-style samples (points and signed distances) and save them as .npz");
    sample->add_option("mesh", args->mesh, "Input mesh")->required();
    sample->add_option("-n,--count", args->count, "Number of samples")->required()->check(wholeNumber(1, std::uint64_t(1) << 34));
    sample->add_option("-o,--output", args->output, "Output .npz with points (n, 3) and sdf (n,), float32, and the channels asked for")->required();
    sample->add_option("--channels", args->channels,
                       "What each sample holds, comma-separated: sdf (always), " + describeChannels() +
                           "; each as (n, width) float32 or int32, (n,) for width 1")
        ->capture_default_str();
    addSampleOptions(*sample, args->settings);
    sample->add_option("--padding", args->settings.padding, "Margin of the box the uniform samples fill, as a fraction of the mesh's longest side")
        ->check(finiteRange(0.0, 100.0))
        ->capture_default_str();
    addThreadsOption(*sample, args->threads);
    sample->footer("Noise standard deviations are sqrt(variance) x the normalized radius: 1.03 x the farthest vertex's distance from the bounding box centre.");
    sample->callback([args] { runSample(*args); });
}

} // namespace sdfgen::cli
