#pragma once
#include "render/gl.hpp"

#include <glm/mat4x4.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>
#include <initializer_list>
#include <string>
#include <unordered_map>

namespace sdfgen::render {

// The folder of GLSL files: $SDFGEN_SHADER_DIR when set, else shaders/ beside the executable or
// one level up (an installed or build-tree binary), else the source tree's shaders/ (compiled in).
// Throws Error naming the places it looked when none has the files.
std::string shaderDirectory();

// A linked vertex + fragment (or compute) program built from files in shaderDirectory(). Compile and link
// errors throw Error with the file name and the driver's log.
class Program {
public:
    Program(const std::string& vertexFile, const std::string& fragmentFile);
    // A compute program from one file.
    explicit Program(const std::string& computeFile);
    ~Program();
    Program(const Program&) = delete;
    Program& operator=(const Program&) = delete;

    void use() const { glUseProgram(id_); }
    GLuint id() const { return id_; }

    // Uniform setters (the program must be in use); unknown names are ignored, as GL does.
    void set(const char* name, int value);
    void set(const char* name, float value);
    void set(const char* name, const glm::vec2& value);
    void set(const char* name, const glm::vec3& value);
    void set(const char* name, const glm::ivec3& value);
    void set(const char* name, const glm::vec4& value);
    void set(const char* name, const glm::mat4& value);

private:
    void link(std::initializer_list<GLuint> shaders, const std::string& name);
    GLint location(const char* name);
    GLuint id_ = 0;
    std::unordered_map<std::string, GLint> locations_;
};

} // namespace sdfgen::render
