#include "app/generation.hpp"
#include "render/band_display.hpp"
#include "sdfgen/error.hpp"
#include "sdfgen/formats.hpp"
#include "sdfgen/model.hpp"

namespace sdfgen::app {

void BackgroundTask::start(int threads, std::function<void(RunControl&)> work) {
    stop();
    cancel_ = false;
    finished_ = false;
    progress_ = 0.0;
    error_.clear();
    started_ = std::chrono::steady_clock::now();
    thread_ = std::thread([this, threads, work = std::move(work)] {
        // Made first, so that Cancel and the thread count reach every step.
        RunControl control;
        control.threads = threads;
        control.cancel = &cancel_;
        control.progress = [this](double fraction) { progress_ = fraction; };
        std::string error;
        try {
            work(control);
        } catch (const Cancelled&) {
            error = "cancelled";
        } catch (const std::exception& e) {
            error = e.what();
            if (error.empty()) error = "failed";
        }
        if (error.empty() && cancel_) error = "cancelled"; // asked after the work's last check: its result is dropped
        error_ = error;
        seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
        finished_ = true;
    });
}

void BackgroundTask::stop() {
    if (!thread_.joinable()) return;
    cancel_ = true;
    thread_.join();
}

double BackgroundTask::elapsed() const {
    if (finished_) return seconds_;
    if (!thread_.joinable()) return 0.0;
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
}

bool BackgroundTask::finish(std::string& error, double& seconds) {
    if (!thread_.joinable() || !finished_) return false;
    thread_.join();
    error = error_;
    seconds = seconds_;
    return true;
}

std::shared_ptr<const Model> MeshModel::get(const RunControl& control, std::vector<std::string>* warnings) {
    std::lock_guard<std::mutex> lock(mutex_);
    return built(control, warnings);
}

std::shared_ptr<const Model> MeshModel::getWithoutWaiting(const RunControl& control) {
    std::unique_lock<std::mutex> lock(mutex_, std::try_to_lock);
    return lock ? built(control, nullptr) : nullptr;
}

std::shared_ptr<const Model> MeshModel::built(const RunControl& control, std::vector<std::string>* warnings) {
    if (!model_) {
        RunControl building = control;
        std::vector<std::string> said;
        building.warn = [&said](const std::string& warning) { said.push_back(warning); };
        model_ = std::make_shared<const Model>(Mesh(*mesh_), building);
        warnings_ = std::move(said);
    }
    if (warnings) *warnings = warnings_;
    return model_;
}

void Generation::start(std::shared_ptr<MeshModel> model, const BakeSettings& settings, const GenerationOptions& options) {
    stop();
    result_.reset();
    warnings_.clear();
    BackgroundTask::start(options.threads, [this, model, settings](RunControl& control) {
        // The tree, when this bake builds it, takes a small share of the bar: a fraction of the bake's time.
        std::vector<std::string> meshWarnings;
        const std::shared_ptr<const Model> ready = model->get(control.phase(0.0, 0.1), &meshWarnings);
        warnings_ = std::move(meshWarnings);
        control.warn = [this](const std::string& warning) { warnings_.push_back(warning); };
        result_ = ready->bake(settings, control.phase(0.1, 1.0));
    });
}

bool Generation::collect(std::optional<BakeResult>& result, std::string& error, std::vector<std::string>& warnings, double& seconds) {
    if (!finish(error, seconds)) return false;
    if (error == "cancelled") error = "generation cancelled";
    if (error.empty()) result = std::move(result_); // none when cancelled after it was made
    result_.reset();
    warnings = std::move(warnings_);
    warnings_.clear();
    return true;
}

void FieldLoad::start(const std::string& path, int threads, int textureLimit) {
    stop();
    path_ = path;
    result_.reset();
    BackgroundTask::start(threads, [this, path, textureLimit, delay = delayPerReportMs](RunControl& control) {
        if (delay > 0) {
            control.progress = [report = control.progress, delay, cancel = control.cancel](double fraction) {
                const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(delay);
                while (std::chrono::steady_clock::now() < until && !*cancel) std::this_thread::sleep_for(std::chrono::milliseconds(10));
                report(fraction);
            };
        }
        LoadedField loaded;
        // Reading takes most of the time; a band field's resampling for the views the rest.
        AnyField file = loadAnyField(path, control.phase(0.0, 0.85));
        if (file.isBand()) {
            render::BandDisplay shown = render::bandDisplay(file.band(), textureLimit, control.phase(0.85, 1.0));
            loaded.field = std::move(shown.field);
            loaded.bandLine = std::move(shown.line);
            loaded.band = std::move(file.band());
        } else {
            loaded.field = std::move(file.dense());
        }
        result_ = std::move(loaded);
    });
}

bool FieldLoad::collect(std::optional<LoadedField>& result, std::string& error) {
    double seconds = 0.0;
    if (!finish(error, seconds)) return false;
    if (error.empty()) result = std::move(result_); // none when cancelled after it was made
    result_.reset();
    return true;
}

void FieldComparison::start(std::shared_ptr<const Field> shown, std::shared_ptr<const SparseField> band, const std::string& path, int threads) {
    stop();
    path_ = path;
    result_.reset();
    BackgroundTask::start(threads, [this, shown, band, path](RunControl& control) {
        // Reading takes most of the time; the comparison (one pass) the rest.
        const Field other = loadField(path, control.phase(0.0, 0.8));
        std::optional<Field> bandDense;
        if (band) bandDense = band->toDense();
        const Field& mine = bandDense ? *bandDense : *shown;
        ComparedFields compared;
        compared.difference = compareFields(mine, other, 0.0, &compared.signDifferences, control.phase(0.8, 1.0));
        compared.grid = mine.grid;
        result_ = std::move(compared);
    });
}

bool FieldComparison::collect(std::optional<ComparedFields>& result, std::string& error) {
    double seconds = 0.0;
    if (!finish(error, seconds)) return false;
    if (error.empty()) result = std::move(result_); // none when cancelled after it was made
    result_.reset();
    return true;
}

} // namespace sdfgen::app
