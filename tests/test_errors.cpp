// The exception hierarchy (core/error.h) and ML_ASSERT (core/assert.h).
#include <gtest/gtest.h>

// Whether the library was built with its assertions on: the same test as core/assert.h makes,
// taken before this file turns them on for itself below.
#if !defined(NDEBUG) || defined(MANYLIGHT_ASSERTS)
constexpr bool kLibraryAsserts = true;
#else
constexpr bool kLibraryAsserts = false;
#endif

// This file checks the macro itself whatever the build type.
#ifndef MANYLIGHT_ASSERTS
#define MANYLIGHT_ASSERTS
#endif

#include <string>

#include "core/assert.h"
#include "core/error.h"
#include "film/film.h"

using namespace ml;

TEST(Errors, OneHierarchy) {
    EXPECT_THROW(throw InputError(FileLoc{"a.pbrt", 3, 4}, "bad"), Error);
    EXPECT_THROW(throw UsageError("bad option"), Error);
    EXPECT_THROW(throw InternalError("broken"), Error);
    // Each is told apart from the others.
    EXPECT_THROW(throw UsageError("bad option"), UsageError);
    try {
        throw InputError(FileLoc{"a.pbrt", 3, 4}, "bad");
    } catch (const UsageError&) {
        ADD_FAILURE() << "an InputError caught as UsageError";
    } catch (const InputError& e) {
        EXPECT_EQ(e.loc().to_string(), "a.pbrt:3:4");
    }
}

TEST(Errors, InternalErrorNamesWhereItWasRaised) {
    try {
        throw InternalError("broken");
    } catch (const InternalError& e) {
        std::string what = e.what();
        EXPECT_NE(what.find("test_errors.cpp:"), std::string::npos) << what;
        EXPECT_NE(what.find("broken"), std::string::npos) << what;
    }
}

TEST(Errors, AssertThrowsInternalErrorWithTheCondition) {
    ASSERT_TRUE(ML_ASSERTS_ENABLED);
    int three = 3;
    EXPECT_NO_THROW(ML_ASSERT(three == 3, "never"));
    try {
        ML_ASSERT(three == 4, "three is " + std::to_string(three));
        ADD_FAILURE() << "no exception";
    } catch (const InternalError& e) {
        std::string what = e.what();
        EXPECT_NE(what.find("assertion failed: three == 4: three is 3"), std::string::npos) << what;
        EXPECT_NE(what.find("test_errors.cpp:"), std::string::npos) << what;
    }
}

TEST(Errors, FilmRejectsAPixelOffTheFilm) {
    if (!kLibraryAsserts) GTEST_SKIP() << "a Release build without MANYLIGHT_ASSERTS";
    Film film(4, 3);
    EXPECT_NO_THROW(film.add_sample(Point2i{3, 2}, RGB(1.f), 1.f));
    EXPECT_THROW(film.add_sample(Point2i{4, 0}, RGB(1.f), 1.f), InternalError);
    EXPECT_THROW(film.add_sample(Point2i{0, -1}, RGB(1.f), 1.f), InternalError);
}
