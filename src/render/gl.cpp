#include "render/gl.hpp"
#include "sdfgen/error.hpp"

#include <cstdio>

namespace sdfgen::render {

void loadGl(GLADloadfunc getProcAddress, const std::string& contextName) {
    const int version = gladLoadGL(getProcAddress);
    if (version == 0) throw Error(contextName + ": could not load the OpenGL entry points");
    const int major = GLAD_VERSION_MAJOR(version), minor = GLAD_VERSION_MINOR(version);
    if (major < 4 || (major == 4 && minor < 5)) {
        throw Error(contextName + ": OpenGL 4.5 core is needed, the driver offers " + std::to_string(major) + "." +
                    std::to_string(minor));
    }
    installDebugOutput();
}

#ifndef NDEBUG
static void GLAPIENTRY debugCallback(GLenum, GLenum type, GLuint, GLenum severity, GLsizei, const GLchar* message,
                                     const void*) {
    if (severity == GL_DEBUG_SEVERITY_NOTIFICATION) return;
    std::fprintf(stderr, "sdfgen: GL %s: %s\n", type == GL_DEBUG_TYPE_ERROR ? "error" : "warning", message);
}
#endif

void installDebugOutput() {
#ifndef NDEBUG
    GLint flags = 0;
    glGetIntegerv(GL_CONTEXT_FLAGS, &flags);
    if (!(flags & GL_CONTEXT_FLAG_DEBUG_BIT)) return;
    glEnable(GL_DEBUG_OUTPUT);
    glEnable(GL_DEBUG_OUTPUT_SYNCHRONOUS);
    glDebugMessageCallback(debugCallback, nullptr);
#endif
}

} // namespace sdfgen::render
