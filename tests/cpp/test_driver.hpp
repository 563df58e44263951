// A minimal self-contained test driver (no framework to download).
//
//     TEST(name) { CHECK(cond); CHECK_NEAR(a, b, tol); CHECK_THROWS(expr, Exception); }
//
// Every failed check prints file:line and what failed, and the test goes on. main() (in
// test_main.cpp) runs every registered test, or those whose name contains an argument,
// prints "N passed, N failed" and returns nonzero when a test failed. A test that throws an
// unexpected exception fails.
#pragma once

#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <sstream>
#include <string>
#include <vector>

namespace test_driver {

struct TestCase {
  const char* name;
  void (*run)();
};

inline std::vector<TestCase>& registry() {
  static std::vector<TestCase> tests;
  return tests;
}

inline int& failed_checks() {  // in the running test
  static int n = 0;
  return n;
}

struct Registrar {
  Registrar(const char* name, void (*run)()) { registry().push_back({name, run}); }
};

inline void fail(const char* file, int line, const std::string& what) {
  std::printf("  %s:%d: FAILED %s\n", file, line, what.c_str());
  ++failed_checks();
}

inline void check_near(double a, double b, double tol, const char* a_text, const char* b_text, const char* tol_text,
                       const char* file, int line) {
  if (std::abs(a - b) <= tol) return;  // false for NaN
  std::ostringstream msg;
  msg.precision(17);
  msg << "CHECK_NEAR(" << a_text << ", " << b_text << ", " << tol_text << "): " << a << " vs " << b
      << ", |difference| = " << std::abs(a - b) << " > " << tol;
  fail(file, line, msg.str());
}

// Called before every test (fixtures.hpp reseeds its random numbers there, so that a test's
// inputs do not depend on which tests ran before it).
inline std::vector<void (*)()>& before_each() {
  static std::vector<void (*)()> hooks;
  return hooks;
}

inline int run_all(int argc, char** argv) {
  int passed = 0, failed = 0;
  for (const TestCase& t : registry()) {
    bool selected = argc < 2;
    for (int a = 1; a < argc; ++a) selected = selected || std::strstr(t.name, argv[a]) != nullptr;
    if (!selected) continue;
    failed_checks() = 0;
    for (void (*hook)() : before_each()) hook();
    try {
      t.run();
    } catch (const std::exception& e) {
      fail(t.name, 0, std::string("unexpected exception: ") + e.what());
    } catch (...) {
      fail(t.name, 0, "unexpected exception of unknown type");
    }
    std::printf("%s %s\n", failed_checks() ? "FAIL" : "ok  ", t.name);
    ++(failed_checks() ? failed : passed);
  }
  std::printf("%d passed, %d failed\n", passed, failed);
  return failed || passed == 0 ? 1 : 0;
}

}  // namespace test_driver

#define TEST(name)                                                                  \
  static void test_##name();                                                        \
  static const ::test_driver::Registrar test_registrar_##name(#name, &test_##name); \
  static void test_##name()

// Variadic so that a condition with template commas needs no extra parentheses.
#define CHECK(...)                                                                          \
  do {                                                                                      \
    if (!(__VA_ARGS__)) ::test_driver::fail(__FILE__, __LINE__, "CHECK(" #__VA_ARGS__ ")"); \
  } while (0)

#define CHECK_NEAR(a, b, tol) ::test_driver::check_near((a), (b), (tol), #a, #b, #tol, __FILE__, __LINE__)

#define CHECK_THROWS(expr, Exception)                                                                        \
  do {                                                                                                       \
    bool test_thrown_ = false;                                                                               \
    try {                                                                                                    \
      (void)(expr);                                                                                          \
    } catch (const Exception&) {                                                                             \
      test_thrown_ = true;                                                                                   \
    } catch (...) {                                                                                          \
      test_thrown_ = true;                                                                                   \
      ::test_driver::fail(__FILE__, __LINE__, "CHECK_THROWS(" #expr ", " #Exception "): another exception"); \
    }                                                                                                        \
    if (!test_thrown_)                                                                                       \
      ::test_driver::fail(__FILE__, __LINE__, "CHECK_THROWS(" #expr ", " #Exception "): nothing thrown");    \
  } while (0)
