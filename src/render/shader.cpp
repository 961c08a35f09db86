#include "render/shader.hpp"
#include "sdfgen/error.hpp"

#include <glm/gtc/type_ptr.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>
#include <vector>

namespace sdfgen::render {

namespace fs = std::filesystem;

std::string shaderDirectory() {
    std::vector<fs::path> candidates;
    if (const char* env = std::getenv("SDFGEN_SHADER_DIR"); env && *env) candidates.emplace_back(env);
    char self[4096];
    const ssize_t n = readlink("/proc/self/exe", self, sizeof(self) - 1);
    if (n > 0) {
        self[n] = '\0';
        const fs::path dir = fs::path(self).parent_path();
        candidates.push_back(dir / "shaders");
        candidates.push_back(dir.parent_path() / "shaders");
        candidates.push_back(dir.parent_path() / "share" / "sdfgen" / "shaders"); // cmake --install
    }
    candidates.push_back(fs::path(SDFGEN_SOURCE_DIR) / "shaders");
    std::string tried;
    for (const fs::path& c : candidates) {
        std::error_code ec;
        if (fs::exists(c / "fullscreen.vert", ec)) return c.string();
        tried += (tried.empty() ? "" : ", ") + c.string();
    }
    throw Error("no shader folder found (looked in " + tried + "; set SDFGEN_SHADER_DIR)");
}

namespace {

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw Error(path + ": cannot read the shader");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// GLSL has no includes: a line `#include "FILE"` is replaced by FILE from the same folder (shared
// code such as colormap.glsl).
std::string expandIncludes(const std::string& source, const fs::path& folder) {
    std::istringstream in(source);
    std::string out, line;
    while (std::getline(in, line)) {
        const std::string directive = "#include \"";
        if (line.rfind(directive, 0) == 0 && line.size() > directive.size() + 1 && line.back() == '"') {
            out += readFile((folder / line.substr(directive.size(), line.size() - directive.size() - 1)).string());
        } else {
            out += line;
        }
        out += '\n';
    }
    return out;
}

GLuint compile(GLenum stage, const std::string& path) {
    const std::string source = expandIncludes(readFile(path), fs::path(path).parent_path());
    const GLuint shader = glCreateShader(stage);
    const char* text = source.c_str();
    glShaderSource(shader, 1, &text, nullptr);
    glCompileShader(shader);
    GLint ok = 0;
    glGetShaderiv(shader, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        glGetShaderiv(shader, GL_INFO_LOG_LENGTH, &length);
        std::string log(std::size_t(std::max(length, 1)), '\0');
        glGetShaderInfoLog(shader, length, nullptr, log.data());
        glDeleteShader(shader);
        while (!log.empty() && (log.back() == '\n' || log.back() == '\0')) log.pop_back();
        throw Error(path + ": shader does not compile: " + log);
    }
    return shader;
}

} // namespace

Program::Program(const std::string& vertexFile, const std::string& fragmentFile) {
    const std::string dir = shaderDirectory();
    const GLuint vs = compile(GL_VERTEX_SHADER, dir + "/" + vertexFile);
    GLuint fs = 0;
    try {
        fs = compile(GL_FRAGMENT_SHADER, dir + "/" + fragmentFile);
    } catch (...) {
        glDeleteShader(vs);
        throw;
    }
    link({vs, fs}, vertexFile + " + " + fragmentFile);
}

Program::Program(const std::string& computeFile) {
    link({compile(GL_COMPUTE_SHADER, shaderDirectory() + "/" + computeFile)}, computeFile);
}

void Program::link(std::initializer_list<GLuint> shaders, const std::string& name) {
    id_ = glCreateProgram();
    for (GLuint shader : shaders) glAttachShader(id_, shader);
    glLinkProgram(id_);
    for (GLuint shader : shaders) glDeleteShader(shader);
    GLint ok = 0;
    glGetProgramiv(id_, GL_LINK_STATUS, &ok);
    if (!ok) {
        GLint length = 0;
        glGetProgramiv(id_, GL_INFO_LOG_LENGTH, &length);
        std::string log(std::size_t(std::max(length, 1)), '\0');
        glGetProgramInfoLog(id_, length, nullptr, log.data());
        glDeleteProgram(id_);
        throw Error(name + ": program does not link: " + log);
    }
}

Program::~Program() { glDeleteProgram(id_); }

GLint Program::location(const char* name) {
    auto it = locations_.find(name);
    if (it == locations_.end()) it = locations_.emplace(name, glGetUniformLocation(id_, name)).first;
    return it->second;
}

void Program::set(const char* name, int value) { glUniform1i(location(name), value); }
void Program::set(const char* name, float value) { glUniform1f(location(name), value); }
void Program::set(const char* name, const glm::vec2& v) { glUniform2fv(location(name), 1, glm::value_ptr(v)); }
void Program::set(const char* name, const glm::vec3& v) { glUniform3fv(location(name), 1, glm::value_ptr(v)); }
void Program::set(const char* name, const glm::ivec3& v) { glUniform3iv(location(name), 1, glm::value_ptr(v)); }
void Program::set(const char* name, const glm::vec4& v) { glUniform4fv(location(name), 1, glm::value_ptr(v)); }
void Program::set(const char* name, const glm::mat4& m) { glUniformMatrix4fv(location(name), 1, GL_FALSE, glm::value_ptr(m)); }

} // namespace sdfgen::render
