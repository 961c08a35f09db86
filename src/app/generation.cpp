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
    started_ = std::chrono::steady_clock::now();
    thread_ = std::thread([this, mesh, settings, options] {
        std::optional<BakeResult> result;
        std::string error;
        try {
            const Model model(*mesh);
            RunControl control;
            control.threads = options.threads;
            control.cancel = &cancel_;
            control.progress = [this](double fraction) { progress_ = fraction; };
            result = model.bake(settings, control);
        } catch (const Cancelled&) {
            error = "generation cancelled";
        } catch (const std::exception& e) {
            error = e.what();
        }
        std::lock_guard<std::mutex> lock(mutex_);
        result_ = std::move(result);
        error_ = error;
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

bool Generation::collect(std::optional<BakeResult>& result, std::string& error, double& seconds) {
    if (!thread_.joinable() || !finished_) return false;
    thread_.join();
    std::lock_guard<std::mutex> lock(mutex_);
    result = std::move(result_);
    result_.reset();
    error = error_;
    seconds = seconds_;
    return true;
}

} // namespace sdfgen::app
