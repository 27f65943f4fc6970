#pragma once
// The program's version, printed by `tsuchi --version`, at the head of every summary and in the
// header of every frame, .pvd and element CSV. CMakeLists.txt checks it against project(VERSION).
namespace tsuchi {

inline constexpr const char* version = "0.1.0";

}  // namespace tsuchi
