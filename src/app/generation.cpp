#include "app/generation.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/model.hpp"

namespace sdfgen::app {

void Generation::start(std::shared_ptr<const Mesh> mesh, const BakeSettings& settings, const GenerationOptions& options) {
    stop();
    cancel_ = false;
    finished_ = false;
    progress_ = 0.0;
    result_.reset();
    error_.clear();
    warnings_.clear();
    started_ = std::chrono::steady_clock::now();
    thread_ = std::thread([this, mesh, settings, options] {
        std::optional<BakeResult> result;
        std::string error;
        std::vector<std::string> warnings;
        // Made first, so that Cancel and the thread count reach the tree build too.
        RunControl control;
        control.threads = options.threads;
        control.cancel = &cancel_;
        control.progress = [this](double fraction) { progress_ = fraction; };
        control.warn = [&warnings](const std::string& warning) { warnings.push_back(warning); };
        try {
            // The tree takes a small share of the bar: it is built in a fraction of the bake's time.
            const Model model(*mesh, control.phase(0.0, 0.1));
            result = model.bake(settings, control.phase(0.1, 1.0));
        } catch (const Cancelled&) {
            error = "generation cancelled";
        } catch (const std::exception& e) {
            error = e.what();
        }
        std::lock_guard<std::mutex> lock(mutex_);
        result_ = std::move(result);
        error_ = error;
        warnings_ = std::move(warnings);
        seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
        finished_ = true;
    });
}

void Generation::stop() {
    if (!thread_.joinable()) return;
    cancel_ = true;
    thread_.join();
}

double Generation::elapsed() const {
    if (finished_) return seconds_;
    if (!thread_.joinable()) return 0.0;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
}

bool Generation::collect(std::optional<BakeResult>& result, std::string& error, std::vector<std::string>& warnings, double& seconds) {
    if (!thread_.joinable() || !finished_) return false;
    thread_.join();
    std::lock_guard<std::mutex> lock(mutex_);
    result = std::move(result_);
    result_.reset();
    error = error_;
    warnings = std::move(warnings_);
    warnings_.clear();
    seconds = seconds_;
    return true;
}

} // namespace sdfgen::app
