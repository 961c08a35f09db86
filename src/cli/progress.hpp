#pragma once
#include <chrono>
#include <cstdio>
#include <functional>

namespace sdfgen::cli {

// Seconds since construction.
class Stopwatch {
public:
    double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

private:
    std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// A progress bar on stderr when it is a terminal; nothing at all on a pipe or file.
class ProgressBar {
public:
    ProgressBar();
    ~ProgressBar();
    // The callback for RunControl::progress (or empty when there is no terminal).
    std::function<void(double)> callback();

private:
    void draw(double fraction);
    bool terminal_;
    bool drawn_ = false;
    int lastPercent_ = -1;
};

} // namespace sdfgen::cli
