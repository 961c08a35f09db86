#pragma once
#include <stdexcept>
#include <string>

namespace sdfgen {

// A user-facing failure. The message is one line naming the file (when there is one) and the problem.
class Error : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Thrown by long-running work when its cancel flag is raised.
class Cancelled : public Error {
public:
    Cancelled() : Error("cancelled") {}
};

// An allocation that failed, named: "PATH: out of memory while DOING" (what the up-front memory
// checks missed). Its own type, so that a caller that set a memory limit (batch's --memory) can
// say which limit it was.
class OutOfMemoryError : public Error {
public:
    using Error::Error;
};

} // namespace sdfgen
