# Builds each kernel check (SRC/*_check.cpp) into OUT/<name>, with simd_probe.cpp linked in, for one
# target; scripts/arm_check.sh runs it once per target (aarch64, and each x86 instruction set) with -j.
# Set by the caller: SRC, OUT, CXX, ISAFLAGS, LDFLAGS_EXTRA, EXPECT (the vector width, bytes).
# OUT/flags holds the compile line's flags and is rewritten only when they change, so a changed
# flag set rebuilds and an unchanged one rebuilds only what its headers (-MMD) say changed.
HERE := $(dir $(lastword $(MAKEFILE_LIST)))
KERNELS := $(abspath $(HERE)../../modules/dynblur/src/restore/kernels)
TESTS := $(wildcard $(SRC)/*_check.cpp)
BINS := $(patsubst $(SRC)/%.cpp,$(OUT)/%,$(TESTS))
CXXFLAGS := -std=c++17 -O3 -DNDEBUG -fno-math-errno -Wall -Wextra $(ISAFLAGS) \
            -include $(KERNELS)/cv_isa_from_compiler.hpp -I$(KERNELS)/../.. -I/usr/include/opencv4 -DDYNBLUR_EXPECT_SIMD_WIDTH=$(EXPECT) -MMD -MP

all: $(BINS)

$(OUT)/%.o: $(SRC)/%.cpp $(OUT)/flags
	$(CXX) $(CXXFLAGS) -c $< -o $@

$(OUT)/simd_probe.o: $(HERE)simd_probe.cpp $(OUT)/flags
	$(CXX) $(CXXFLAGS) -c $< -o $@

$(OUT)/%: $(OUT)/%.o $(OUT)/simd_probe.o
	$(CXX) $(LDFLAGS_EXTRA) $^ -o $@

.PRECIOUS: $(OUT)/%.o
-include $(wildcard $(OUT)/*.d)
