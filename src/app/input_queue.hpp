#pragma once
// Every GLFW input event in arrival order, fed to Dear ImGui one discrete event per frame.
// Debian's ImGui 1.86 has no input queue of its own: it reads the mouse buttons once per frame, so
// a press and release (or two clicks) between two frames, which happens whenever a frame is slow,
// would be lost or merged. Here, per frame, all pointer moves and typed characters up to the next
// discrete event (a button, wheel or key change, or a screenshot request) are applied, then that
// one event, and the rest waits for the next frame.
#include <deque>

struct GLFWwindow;

namespace sdfgen::app {

struct InputEvent {
    enum class Type { Move, Button, Scroll, Key, Char, Screenshot } type = Type::Move;
    double x = 0.0, y = 0.0; // Move: cursor position; Scroll: offsets
    int code = 0;            // Button: button; Key: key; Char: codepoint
    int scancode = 0, action = 0, mods = 0;
};

// What one frame took from the queue, for the scene's own handling (camera drags, the wheel).
struct FrameInput {
    double startX = 0.0, startY = 0.0; // cursor at the start of the frame
    double x = 0.0, y = 0.0;           // and after this frame's moves
    int pressed = -1, released = -1;   // the button pressed or released this frame, if any
    int pressMods = 0;
    double wheel = 0.0;
    bool screenshot = false;
};

class InputQueue {
public:
    void push(const InputEvent& event) { events_.push_back(event); }
    bool empty() const { return events_.empty(); }
    // Between ImGui_ImplGlfw_NewFrame and ImGui::NewFrame: takes this frame's events, forwards
    // keys, characters and the wheel to the ImGui backend, and sets io.MousePos / io.MouseDown
    // from the queue's state instead of the backend's once-per-frame poll.
    FrameInput apply(GLFWwindow* window, bool cursorInside);
    bool buttonDown(int button) const { return button >= 0 && button < 3 && down_[button]; }

private:
    std::deque<InputEvent> events_;
    double x_ = -1.0, y_ = -1.0;
    bool down_[3] = {false, false, false};
};

} // namespace sdfgen::app
