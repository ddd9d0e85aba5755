#include <gtest/gtest.h>

#include "common/errors.h"

TEST(Errors, RequireThrowsTypedExceptionWithMessage) {
  try {
    PM_REQUIRE(1 == 2, paramorph::NotClosedError, "mesh has ", 3, " boundary loops");
    FAIL() << "PM_REQUIRE did not throw";
  } catch (const paramorph::MeshError& e) {
    EXPECT_NE(std::string(e.what()).find("mesh has 3 boundary loops"), std::string::npos);
  }
}
