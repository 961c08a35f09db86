#include "cli/progress.hpp"

#include <string>
#include <unistd.h>

namespace sdfgen::cli {

ProgressBar::ProgressBar() : terminal_(isatty(fileno(stderr)) != 0) {}

ProgressBar::~ProgressBar() {
    if (drawn_) std::fputs("\r\033[K", stderr); // leave the line clean for the summary
}

std::function<void(double)> ProgressBar::callback() {
    if (!terminal_) return {};
    return [this](double fraction) { draw(fraction); };
}

void ProgressBar::draw(double fraction) {
    const int percent = int(fraction * 100.0);
    if (percent == lastPercent_) return;
    lastPercent_ = percent;
    constexpr int kWidth = 40;
    const int filled = percent * kWidth / 100;
    std::fprintf(stderr, "\r[%s%s] %3d%%", std::string(std::size_t(filled), '#').c_str(),
                 std::string(std::size_t(kWidth - filled), '.').c_str(), percent);
    std::fflush(stderr);
    drawn_ = true;
}

} // namespace sdfgen::cli
