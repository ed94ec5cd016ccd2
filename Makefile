# The user's entry point (as PX4's `make px4_sitl`): `make sim`, `make test`.
# Both first run `make deps`, which installs missing Debian packages (as root).
SHELL := /bin/bash
.DEFAULT_GOAL := help

# libstdc++-arm-none-eabi-newlib: the Cortex-M7 build's C++ headers (<array>, ...);
# gcc-arm-none-eabi alone is C only.
# libssl-dev: OpenSSL's CMAC (EVP_MAC), the tests' independent check of the link's MAC.
# clang + libclang-rt-14-dev: libFuzzer and the sanitizers for tests/fuzz
# (libclang-rt is only recommended by clang, and deps installs no recommends).
DEBIAN_PACKAGES := cmake ninja-build g++ git gcc-arm-none-eabi libnewlib-arm-none-eabi \
                   libstdc++-arm-none-eabi-newlib python3 \
                   qemu-system-arm libeigen3-dev doctest-dev nlohmann-json3-dev \
                   libcli11-dev libfmt-dev libbenchmark-dev libpugixml-dev libssl-dev \
                   clang libclang-rt-14-dev
FIRMWARE_ELF := build/cortex-m7/port/itp_firmware_mps2_an500.elf
# The RAM budget lives in port/mps2_an500/ram_budget.ld (linker, static_assert
# and `make size` read the same number); `make size RAM_BUDGET=...` overrides
# it for the report only.
RAM_BUDGET ?=
# The road image: the production service for RoadConfig (32 + 32 objects; no
# RAM budget, its figure is reported).
ROAD_FIRMWARE_ELF := build/cortex-m7/port/itp_firmware_mps2_an500_road.elf
# The float low-RAM image: the production service in LowRamConfig (the QPs share
# one storage, which also holds the reference spline's workspace and, between
# cycles, the request being received) with float as the planner's scalar
# (firmware_core_f32). Its budget is issue 12's goal, 128 KiB, checked by `make size`.
F32_FIRMWARE_ELF := build/cortex-m7/port/itp_firmware_mps2_an500_f32.elf
F32_RAM_BUDGET := 131072
# The test image (QP-check service), used by the QEMU QP agreement test only.
TEST_FIRMWARE_ELF := build/cortex-m7/port/itp_firmware_mps2_an500_qp_check.elf
HIL_SIM := build/host-release/hil_sim/hil_sim
# make sim SIM_TARGET=inproc SIM_COUNT=20 for a quick run; the default is the
# 200-scene suite on the Cortex-M7 firmware under QEMU (about 15 minutes),
# then the same suite on the host-port firmware for comparison.
SIM_TARGET ?= qemu
SIM_COUNT ?= 200
# The same suite on this target too, compared with the main run (safety
# outcomes must match; empty: skip).
SIM_COMPARE ?= host
SIM_OUT ?= build/sim

# make fuzz FUZZ_SECONDS=600: every fuzz target for that long (tests/fuzz/run_fuzzers.sh).
# FUZZ_PRESET=fuzz-long: the build for long runs (UBSan, no ASan; docs/fuzzing.md);
# FUZZ_OPTS=-runs=10000000: any libFuzzer options instead of the time limit.
FUZZ_SECONDS ?= 60
FUZZ_PRESET ?= fuzz
FUZZ_OPTS ?= -max_total_time=$(FUZZ_SECONDS)

.PHONY: help deps test sim host-debug host-release cortex-m7 size stack clean fuzz fuzz-build wcet wcet-measure wcet-link

help:
	@echo "make sim    - build everything and run the simulator against the Cortex-M7 firmware under QEMU"
	@echo "make test   - host-debug (ASan+UBSan) tests, cortex-m7 build + size and stack checks,"
	@echo "              host-release tests incl. QEMU, the fuzz targets on their seed corpus"
	@echo "make deps   - install missing Debian packages (idempotent; needs root)"
	@echo "make size   - ARM RAM by module (planner stages, scene, plan, link, stack), fails over the RAM budget;"
	@echo "              the road image's table too (reported, no budget)"
	@echo "make stack  - worst-case stack path from the call graph (-fstack-usage), fails on recursion,"
	@echo "              dynamic frames, unresolved indirect calls or a linker-script stack below bound + margin"
	@echo "make wcet   - the derived worst case per cycle: budgets x measured cost per unit, measured maxima"
	@echo "              (WCET_IMAGE=f32: the float low-RAM image's; also for wcet-measure)"
	@echo "make wcet-measure - measure the costs per unit under QEMU (default + stress suite, long)"
	@echo "make wcet-link - measure the link's share of a cycle (frames, MACs, decode, encode) under QEMU"
	@echo "make fuzz   - run every libFuzzer target for FUZZ_SECONDS seconds (default 60);"
	@echo "              FUZZ_PRESET=fuzz-long (no ASan) and FUZZ_OPTS=-runs=10000000 for long runs"

deps:
	@missing=""; \
	for p in $(DEBIAN_PACKAGES); do \
	  dpkg-query -W -f='$${Status}' $$p 2>/dev/null | grep -q "install ok installed" || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
	  echo "deps: installing$$missing"; \
	  apt-get update && DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends $$missing; \
	else \
	  echo "deps: all Debian packages present"; \
	fi

host-debug:
	cmake --preset host-debug
	cmake --build --preset host-debug

cortex-m7:
	cmake --preset cortex-m7
	cmake --build --preset cortex-m7

fuzz-build:
	cmake --preset $(FUZZ_PRESET)
	cmake --build --preset $(FUZZ_PRESET)

fuzz: deps fuzz-build
	tests/fuzz/run_fuzzers.sh build/$(FUZZ_PRESET)/tests/fuzz $(FUZZ_OPTS)

host-release: cortex-m7
	cmake --preset host-release
	cmake --build --preset host-release

# The derived worst-case bound (issue 12): budgets from itp/config.hpp times the
# costs per unit in tools/wcet_costs.json (docs/performance.md, "Worst case").
# WCET_IMAGE=f32: the float low-RAM image's, with LowRamSizes' budgets and its
# own costs (tools/wcet_costs_f32.json).
WCET_IMAGE ?= default
ifeq ($(WCET_IMAGE),f32)
WCET_ELF := $(F32_FIRMWARE_ELF)
WCET_SIZES := LowRamSizes
WCET_COSTS := tools/wcet_costs_f32.json
WCET_LINK_IMAGE := f32
WCET_OUT ?= build/wcet-f32
else
WCET_ELF := $(FIRMWARE_ELF)
WCET_SIZES := DefaultSizes
WCET_COSTS := tools/wcet_costs.json
WCET_LINK_IMAGE := production
WCET_OUT ?= build/wcet
endif
wcet:
	@python3 tools/wcet_table.py --sizes $(WCET_SIZES) table --costs $(WCET_COSTS) --link-image $(WCET_LINK_IMAGE)

# The link's share of a firmware cycle besides planning (frames in and out, the
# two MACs, Scene decoding and validation, Plan encoding) at each image's largest
# Scene and Plan, measured under QEMU by the crypto_bench images into
# tools/wcet_link_costs.json; `make wcet` adds it to the planner's bound.
wcet-link: cortex-m7
	python3 tools/wcet_table.py link --image production --elf build/cortex-m7/port/itp_crypto_bench_mps2_an500.elf
	python3 tools/wcet_table.py link --image road --elf build/cortex-m7/port/itp_crypto_bench_mps2_an500_road.elf
	python3 tools/wcet_table.py link --image f32 --elf build/cortex-m7/port/itp_crypto_bench_mps2_an500_f32.elf

# Re-measure the costs per unit and the maxima under QEMU (-icount): the default
# suite and the stress suite (10 static + 5 dynamic obstacles). WCET_COUNT=200
# WCET_STRESS_COUNT=40 for the full runs (about 15 + 10 minutes, in parallel).
WCET_COUNT ?= 200
WCET_STRESS_COUNT ?= 40
wcet-measure: host-release cortex-m7
	mkdir -p $(WCET_OUT)
	$(HIL_SIM) run --suite default --count $(WCET_COUNT) --seed 1 --target qemu --firmware $(WCET_ELF) \
	  --report $(WCET_OUT)/default.json --trace $(WCET_OUT)/default.jsonl > $(WCET_OUT)/default.txt & \
	$(HIL_SIM) run --suite stress --count $(WCET_STRESS_COUNT) --seed 1 --target qemu --firmware $(WCET_ELF) \
	  --report $(WCET_OUT)/stress.json --trace $(WCET_OUT)/stress.jsonl > $(WCET_OUT)/stress.txt; wait
	python3 tools/wcet_table.py --sizes $(WCET_SIZES) measure --out $(WCET_COSTS) \
	  --default $(WCET_OUT)/default.jsonl --stress $(WCET_OUT)/stress.jsonl \
	  --note "$(notdir $(WCET_ELF)): default suite seed 1 x $(WCET_COUNT) scenes, stress suite seed 1 x $(WCET_STRESS_COUNT) scenes"
	python3 tools/wcet_table.py --sizes $(WCET_SIZES) table --costs $(WCET_COSTS) --link-image $(WCET_LINK_IMAGE)

size: cortex-m7
	@echo "== ARM size report: $(FIRMWARE_ELF) (production image)"
	@arm-none-eabi-size -A -d $(FIRMWARE_ELF) | grep -E "^(section|\.isr_vector|\.text|\.data|\.bss|\.stack)"
	@arm-none-eabi-size $(FIRMWARE_ELF) $(ROAD_FIRMWARE_ELF) $(F32_FIRMWARE_ELF) $(TEST_FIRMWARE_ELF)
	python3 tools/size_report.py --elf $(FIRMWARE_ELF) $(if $(RAM_BUDGET),--budget $(RAM_BUDGET))
	@echo "== The road image (RoadConfig: 32 + 32 objects; its own figure, no budget): $(ROAD_FIRMWARE_ELF)"
	python3 tools/size_report.py --elf $(ROAD_FIRMWARE_ELF) --no-budget
	@echo "== The float low-RAM image (LowRamConfig, float as the scalar; its own budget): $(F32_FIRMWARE_ELF)"
	python3 tools/size_report.py --elf $(F32_FIRMWARE_ELF) --budget $(F32_RAM_BUDGET)
	@echo "== The test image (QP check; never flashed, no budget): $(TEST_FIRMWARE_ELF)"
	set -o pipefail; python3 tools/size_report.py --elf $(TEST_FIRMWARE_ELF) --no-budget | grep -E "^(RAM by|  QP-check|total)"

# The cortex-m7 build writes .su/.ci files next to its objects (ITP_STACK_USAGE).
stack: cortex-m7
	@echo "== Stack analysis: $(FIRMWARE_ELF)"
	python3 tools/stack_analysis.py --build build/cortex-m7 --elf $(FIRMWARE_ELF) --json build/cortex-m7/stack_analysis.json
	@echo "== Stack analysis, the road image (checked against its .stack): $(ROAD_FIRMWARE_ELF)"
	python3 tools/stack_analysis.py --build build/cortex-m7 --elf $(ROAD_FIRMWARE_ELF) --quiet
	@echo "== Stack analysis, the float image (checked against its .stack): $(F32_FIRMWARE_ELF)"
	python3 tools/stack_analysis.py --build build/cortex-m7 --elf $(F32_FIRMWARE_ELF) --quiet
	@echo "== Stack analysis, the test image (its own STACK_SIZE): $(TEST_FIRMWARE_ELF)"
	python3 tools/stack_analysis.py --build build/cortex-m7 --elf $(TEST_FIRMWARE_ELF) --quiet

test: deps
	$(MAKE) --no-print-directory host-debug
	ctest --preset host-debug
	$(MAKE) --no-print-directory size
	$(MAKE) --no-print-directory stack
	$(MAKE) --no-print-directory host-release
	ctest --preset host-release
	$(MAKE) --no-print-directory fuzz-build FUZZ_PRESET=fuzz
	ctest --preset fuzz

sim: deps host-release
	$(HIL_SIM) ping --target qemu --firmware $(FIRMWARE_ELF) --count 3 --garbage
	$(HIL_SIM) run --suite default --count $(SIM_COUNT) --seed 1 --target $(SIM_TARGET) \
	  --firmware $(if $(filter qemu,$(SIM_TARGET)),$(FIRMWARE_ELF),build/host-release/port/itp_firmware_host) \
	  --report $(SIM_OUT)/report.json --plots $(SIM_OUT)/plots --trace $(SIM_OUT)/trace.jsonl
ifneq ($(SIM_COMPARE),)
	$(HIL_SIM) run --suite default --count $(SIM_COUNT) --seed 1 --target $(SIM_COMPARE) \
	  --firmware $(if $(filter qemu,$(SIM_COMPARE)),$(FIRMWARE_ELF),build/host-release/port/itp_firmware_host) \
	  --report $(SIM_OUT)/report-$(SIM_COMPARE).json
	$(HIL_SIM) compare $(SIM_OUT)/report.json $(SIM_OUT)/report-$(SIM_COMPARE).json --json $(SIM_OUT)/agreement.json
endif
	@echo "report: $(SIM_OUT)/report.json, plots: $(SIM_OUT)/plots/index.html"

clean:
	rm -rf build
