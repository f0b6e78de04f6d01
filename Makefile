# SPDX-License-Identifier: MIT
# Periscope - build, run and test.
#   make run     the viewer on the simulated board with the bundled panorama
#   make test    the tests a developer runs after each change (unit, golden, tools, desktop, firmware; minutes)
#   make check   everything CI runs: make test, clang, sanitizers, valgrind, VM, images, cross-architecture, Cortex-M
#   make all     libraries, firmware and host tools
# Conventions: CROSS_COMPILE=prefix-, CC, PKG_CONFIG, PREFIX, DESTDIR, V=1 for full commands.

CROSS_COMPILE ?=
ifeq ($(origin CC),default)
CC := $(CROSS_COMPILE)gcc
endif
ifeq ($(origin AR),default)
AR := $(CROSS_COMPILE)ar
endif
NM ?= $(CROSS_COMPILE)nm
PKG_CONFIG ?= pkg-config
PREFIX ?= /usr/local
DESTDIR ?=
BUILD ?= build

ifeq ($(V),1)
Q :=
else
Q := @
endif

WARN := -Wall -Wextra -Werror -Wshadow -Wstrict-prototypes -Wmissing-prototypes -Wpointer-arith -Wvla
OPT ?= -O2 -g
VERSION := $(shell cat VERSION 2>/dev/null || echo 0)
CFLAGS ?=
BASE_CFLAGS := -std=c11 $(WARN) $(OPT) -MMD -MP
# Each layer compiles with the include paths of what it may use, and no more
# (firmware -> hal -> io -> core, host_tools -> io -> core; scripts/check-layers
# checks every #include against the same table).
# core/ is freestanding: no libc beyond the freestanding headers.
CORE_CFLAGS := $(BASE_CFLAGS) -ffreestanding -Icore
HOSTED_DEFS := -D_DEFAULT_SOURCE -D_POSIX_C_SOURCE=200809L -DPSC_VERSION='"$(VERSION)"'
IO_INC := -Icore -Iio
HAL_INC := $(IO_INC) -Ihal
FW_INC := $(HAL_INC) -Ifirmware
TOOLS_INC := $(IO_INC) -Ihost_tools/lib
TEST_INC := $(FW_INC) -Ihost_tools/lib -Itests/support -Itests/faults

# The image libraries: io's PNG files (libpng) and JPEG decoding (libjpeg),
# which the device program needs too (it packs a JPEG or PNG scene itself,
# io/psc_io_pack_image.h); the host tools and tests add zlib (tests compare
# core's CRC with it).
IO_PKGS := libpng libjpeg
IO_CFLAGS := $(shell $(PKG_CONFIG) --cflags $(IO_PKGS) 2>/dev/null)
IO_LIBS := $(shell $(PKG_CONFIG) --libs $(IO_PKGS) 2>/dev/null || echo -lpng -ljpeg)
IMG_PKGS := libpng libjpeg zlib
IMG_CFLAGS := $(shell $(PKG_CONFIG) --cflags $(IMG_PKGS) 2>/dev/null)
IMG_LIBS := $(shell $(PKG_CONFIG) --libs $(IMG_PKGS) 2>/dev/null || echo -lpng -ljpeg -lz)
# The device backends compiled in, one folder each (hal/<backend>/), and the
# library each needs: the simulated board's PNG captures, DRM/KMS, the SDL2
# desktop window, USB gamepads, GPIO buttons, the kernel's input devices (libevdev:
# touch screens, keyboards, mice, gamepads), V4L2 cameras (MJPEG). All by
# default; a board's `backends` line narrows its cross build (mk/cross.mk: a
# kiosk leaves out SDL2 and the desktop stack it pulls in, and the sim's
# captures). linux (clock, systemd and kernel watchdogs) and the
# sim's deterministic devices need no library and are always in: the VM and
# image tests drive real displays with the sim clock and tour input.
# libgpiod's major version picks its API. The device program links exactly
# these libraries and io's (IO_PKGS): nothing of the host tools.
HAL_ALL_BACKENDS := sim linux fbdev drm sdl usb gpio evdev v4l2
HAL_BACKENDS ?= $(HAL_ALL_BACKENDS)
override HAL_BACKENDS := $(sort linux $(filter $(HAL_ALL_BACKENDS),$(HAL_BACKENDS)))
hal_pkg_sim := libpng
hal_pkg_drm := libdrm
hal_pkg_sdl := sdl2
hal_pkg_usb := libusb-1.0
hal_pkg_gpio := libgpiod
hal_pkg_evdev := libevdev
hal_pkg_v4l2 := libjpeg
HAL_PKGS := $(sort $(foreach b,$(HAL_BACKENDS),$(hal_pkg_$(b))))
HAL_CFLAGS := $(if $(HAL_PKGS),$(shell $(PKG_CONFIG) --cflags $(HAL_PKGS) 2>/dev/null)) \
	$(foreach b,$(filter-out sim $(HAL_BACKENDS),$(HAL_ALL_BACKENDS)),-DPSC_HAL_WITHOUT_$(b)) \
	-DPSC_GPIOD_MAJOR=$(firstword $(subst ., ,$(shell $(PKG_CONFIG) --modversion libgpiod 2>/dev/null || echo 0)))
HAL_LIBS := $(if $(HAL_PKGS),$(shell $(PKG_CONFIG) --libs $(HAL_PKGS) 2>/dev/null))
CMOCKA_CFLAGS := $(shell $(PKG_CONFIG) --cflags cmocka 2>/dev/null)
CMOCKA_LIBS := $(shell $(PKG_CONFIG) --libs cmocka 2>/dev/null || echo -lcmocka)
LDLIBS_HOST := -lm -pthread

CORE_SRC := $(sort $(wildcard core/*/*.c))
# The viewer's vector kernels (core/viewer/psc_viewer_simd.h): the AVX2 one is
# built with -mavx2 for x86-64 targets (and chosen at run time), the baseline
# one with NEON for armhf (SSE2 and arm64's NEON need no flag).
TARGET_MACHINE := $(shell $(CC) -dumpmachine 2>/dev/null)
ifneq ($(filter x86_64-%,$(TARGET_MACHINE)),)
$(BUILD)/obj/core/viewer/psc_viewer_simd_avx2.o: CORE_CFLAGS += -mavx2
endif
ifneq ($(filter arm-%,$(TARGET_MACHINE)),)
$(BUILD)/obj/core/viewer/psc_viewer_simd_vector.o: CORE_CFLAGS += -mfpu=neon
endif
SIM_CAPTURE_SRC := $(if $(filter sim,$(HAL_BACKENDS)),hal/sim/sim_capture_png.c hal/sim/sim_capture_sheet.c,\
	hal/sim/sim_capture_none.c)
HAL_SRC := $(sort $(wildcard hal/*.c) $(filter-out hal/sim/sim_capture_%.c,$(wildcard hal/sim/*.c)) \
	$(SIM_CAPTURE_SRC) $(foreach b,$(filter-out sim,$(HAL_BACKENDS)),$(wildcard hal/$(b)/*.c)))
IO_SRC := $(sort $(wildcard io/*.c))
HOSTLIB_SRC := $(sort $(wildcard host_tools/lib/*/*.c))
# Model import (glTF and the other formats libassimp reads) when this build's
# pkg-config finds libassimp; without it (a cross build without the target's
# libassimp) the tools say so when given a model to import.
ifeq ($(shell $(PKG_CONFIG) --exists assimp 2>/dev/null && echo yes),yes)
HOSTLIB_SRC := $(filter-out host_tools/lib/import/assimp_none.c,$(HOSTLIB_SRC))
IMG_CFLAGS += $(shell $(PKG_CONFIG) --cflags assimp)
IMG_LIBS += $(shell $(PKG_CONFIG) --libs assimp)
else
HOSTLIB_SRC := $(filter-out host_tools/lib/import/assimp.c,$(HOSTLIB_SRC))
endif
# Pose files (POSE.json) and glTF files' node numbers when pkg-config finds json-c; without it the tools say so.
ifeq ($(shell $(PKG_CONFIG) --exists json-c 2>/dev/null && echo yes),yes)
HOSTLIB_SRC := $(filter-out host_tools/lib/import/pose_json_none.c host_tools/lib/import/gltf_numbers_none.c,$(HOSTLIB_SRC))
IMG_CFLAGS += $(shell $(PKG_CONFIG) --cflags json-c)
IMG_LIBS += $(shell $(PKG_CONFIG) --libs json-c)
else
HOSTLIB_SRC := $(filter-out host_tools/lib/import/pose_json.c host_tools/lib/import/gltf_numbers.c,$(HOSTLIB_SRC))
endif
# Proxies simplified (periscope-proxy) when this build's compiler links libmeshoptimizer (it ships no .pc, so
# a test program says); without it the proxies are the model's own triangles and the tool says so.
HAVE_MESHOPT := $(shell printf '\043include <meshoptimizer.h>\nint main(void) { return (int)meshopt_simplifyScale(0, 0, 12); }\n' | \
	$(CC) $(CPPFLAGS) -x c - -o /dev/null -lmeshoptimizer >/dev/null 2>&1 && echo yes)
ifeq ($(HAVE_MESHOPT),yes)
HOSTLIB_SRC := $(filter-out host_tools/lib/bake/simplify_none.c,$(HOSTLIB_SRC))
IMG_LIBS += -lmeshoptimizer
else
HOSTLIB_SRC := $(filter-out host_tools/lib/bake/simplify.c,$(HOSTLIB_SRC))
endif
FW_SRC := $(sort $(wildcard firmware/*.c firmware/scene/*.c))
FW_MAIN := firmware/main.c
TOOL_MAINS := $(sort $(wildcard host_tools/periscope-*.c))
TESTSUP_SRC := $(sort $(wildcard tests/support/*.c))
TEST_MAINS := $(sort $(wildcard tests/test_*.c))

obj = $(patsubst %.c,$(BUILD)/obj/%.o,$(1))

CORE_LIB := $(BUILD)/lib/libpsc_core.a
IO_LIB := $(BUILD)/lib/libpsc_io.a
HAL_LIB := $(BUILD)/lib/libpsc_hal.a
HOST_LIB := $(BUILD)/lib/libpsc_hosttools.a
FW_LIB := $(BUILD)/lib/libpsc_firmware.a
TESTSUP_LIB := $(BUILD)/lib/libpsc_testsupport.a
FIRMWARE := $(BUILD)/bin/periscope
TOOLS := $(patsubst host_tools/%.c,$(BUILD)/bin/%,$(TOOL_MAINS))
# The one list of the programs Periscope ships: the device program and every host tool (host_tools/periscope-*.c).
# The package (scripts/build-deb), its test (test_deb), the tools' test (test_tools) and the manual pages
# (packaging/man/NAME.1, checked by check-man-pages) all take it from $(BUILD)/programs.txt.
PROGRAMS := $(notdir $(FIRMWARE) $(TOOLS))
PROGRAM_LIST := $(BUILD)/programs.txt
TESTS := $(patsubst tests/%.c,$(BUILD)/tests/%,$(TEST_MAINS))

# Objects reached through pattern rules would count as intermediate files and be
# deleted after each link; keep them so a second build compiles nothing.
.SECONDARY:
.PHONY: all deps run test check check-bench-build check-system check-self-contained check-architecture soak check-memcheck vm-test check-core-nofloat \
	check-layers check-clang check-sanitize install clean bench bench-callgrind FORCE
.DEFAULT_GOAL := all

all: $(CORE_LIB) $(IO_LIB) $(FIRMWARE) $(TOOLS) $(PROGRAM_LIST)

# rewritten only when the list changes (FORCE below)
$(PROGRAM_LIST): FORCE
	@mkdir -p $(@D)
	@printf '%s\n' $(PROGRAMS) | cmp -s - $@ || printf '%s\n' $(PROGRAMS) >$@

deps:
	$(Q)sh scripts/install-deps.sh

# ---- objects ---------------------------------------------------------------
$(BUILD)/obj/core/%.o: core/%.c
	@mkdir -p $(@D)
	@$(if $(Q),echo "  CC      $<")
	$(Q)$(CC) $(CORE_CFLAGS) $(CFLAGS) -c $< -o $@

$(BUILD)/obj/io/%.o: io/%.c
	@mkdir -p $(@D)
	@$(if $(Q),echo "  CC      $<")
	$(Q)$(CC) $(BASE_CFLAGS) $(HOSTED_DEFS) $(IO_INC) $(IO_CFLAGS) $(CFLAGS) -c $< -o $@

$(BUILD)/obj/hal/%.o: hal/%.c
	@mkdir -p $(@D)
	@$(if $(Q),echo "  CC      $<")
	$(Q)$(CC) $(BASE_CFLAGS) $(HOSTED_DEFS) $(HAL_INC) $(HAL_CFLAGS) $(CFLAGS) -c $< -o $@

$(BUILD)/obj/firmware/%.o: firmware/%.c
	@mkdir -p $(@D)
	@$(if $(Q),echo "  CC      $<")
	$(Q)$(CC) $(BASE_CFLAGS) $(HOSTED_DEFS) $(FW_INC) $(CFLAGS) -c $< -o $@

$(BUILD)/obj/host_tools/%.o: host_tools/%.c
	@mkdir -p $(@D)
	@$(if $(Q),echo "  CC      $<")
	$(Q)$(CC) $(BASE_CFLAGS) $(HOSTED_DEFS) $(TOOLS_INC) $(IMG_CFLAGS) $(CFLAGS) -c $< -o $@

# tests (and their helpers) see every layer: they drive each one
$(BUILD)/obj/%.o: %.c
	@mkdir -p $(@D)
	@$(if $(Q),echo "  CC      $<")
	$(Q)$(CC) $(BASE_CFLAGS) $(HOSTED_DEFS) $(TEST_INC) $(IMG_CFLAGS) $(HAL_CFLAGS) $(CMOCKA_CFLAGS) $(CFLAGS) -c $< -o $@

$(BUILD)/lib/%.a:
	@mkdir -p $(@D)
	@$(if $(Q),echo "  AR      $@")
	$(Q)rm -f $@ && $(AR) rcs $@ $^

# The backend table is compiled for this build's HAL_BACKENDS: recompile it
# when the list changes (the file's time moves only then).
$(BUILD)/obj/hal/psc_hal_registry.o: $(BUILD)/hal-backends.txt
$(BUILD)/hal-backends.txt: FORCE
	@mkdir -p $(@D)
	@echo '$(HAL_BACKENDS)' | cmp -s - $@ || echo '$(HAL_BACKENDS)' >$@
FORCE:

$(CORE_LIB): $(call obj,$(CORE_SRC))
$(IO_LIB): $(call obj,$(IO_SRC))
$(HAL_LIB): $(call obj,$(HAL_SRC))
$(HOST_LIB): $(call obj,$(HOSTLIB_SRC))
$(FW_LIB): $(call obj,$(filter-out $(FW_MAIN),$(FW_SRC)))
$(TESTSUP_LIB): $(call obj,$(TESTSUP_SRC))

# Dependencies point one way: firmware -> hal -> io -> core, host_tools -> io -> core.
# The device program links its backends' libraries, io's image libraries and nothing of the host tools.
$(FIRMWARE): $(call obj,$(FW_MAIN)) $(FW_LIB) $(HAL_LIB) $(IO_LIB) $(CORE_LIB)
	@mkdir -p $(@D)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(HAL_LIBS) $(IO_LIBS) $(LDLIBS_HOST)

$(BUILD)/bin/%: $(BUILD)/obj/host_tools/%.o $(HOST_LIB) $(IO_LIB) $(CORE_LIB)
	@mkdir -p $(@D)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(IMG_LIBS) $(LDLIBS_HOST)

# The counting allocator and I/O shim (tests/faults/) replaces malloc and open: linked as an object into
# the programs that count, never from the archive (which would hand it to every program calling malloc).
$(BUILD)/tests/test_faults $(BUILD)/tests/test_soak: $(BUILD)/obj/tests/faults/tsup_faults.o

$(BUILD)/tests/%: $(BUILD)/obj/tests/%.o $(TESTSUP_LIB) $(FW_LIB) $(HAL_LIB) $(HOST_LIB) $(IO_LIB) $(CORE_LIB)
	@mkdir -p $(@D)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(CMOCKA_LIBS) $(HAL_LIBS) $(IMG_LIBS) $(LDLIBS_HOST)

-include $(shell find $(BUILD)/obj -name '*.d' 2>/dev/null)

# Per-concern make fragments (cross builds, microcontroller builds, images): mk/*.mk.
-include $(sort $(wildcard mk/*.mk))

# ---- run: the viewer on the simulated board --------------------------------
SAMPLE_JPG := assets/pannellum-examplepano.jpg
SAMPLE_PACK := out/sample.pano
SIM_DISPLAY := $(shell sh scripts/board-key sim display_size)
SIM_PACK_FORMAT := $(shell sh scripts/board-pack-format sim)

$(SAMPLE_PACK): $(SAMPLE_JPG) $(BUILD)/bin/periscope-pack boards/sim/board.conf
	@mkdir -p $(@D)
	$(BUILD)/bin/periscope-pack $(SAMPLE_JPG) -o $@ --display $(or $(SIM_DISPLAY),640x480) --format $(or $(SIM_PACK_FORMAT),rgb888)

# The sample as a tiled pack (periscope-pack --tiled): the tiled scene under valgrind (check-memcheck)
SAMPLE_TILED := out/sample-tiled.pano
$(SAMPLE_TILED): $(SAMPLE_JPG) $(BUILD)/bin/periscope-pack boards/sim/board.conf
	@mkdir -p $(@D)
	$(BUILD)/bin/periscope-pack $(SAMPLE_JPG) -o $@ --display $(or $(SIM_DISPLAY),640x480) --format $(or $(SIM_PACK_FORMAT),rgb888) --tiled --quiet

# The sample character: Thom (assets/thom, CC0) with his two actions, skinned from Thom2's bones.
THOM := assets/thom
SAMPLE_CHARACTER := out/thom.ppk
$(SAMPLE_CHARACTER): $(THOM)/Thom.mdl $(THOM)/Thom2.mdl $(THOM)/ResoluteWalk.act $(THOM)/Wave.act $(BUILD)/bin/periscope-patch
	@mkdir -p $(@D)
	$(BUILD)/bin/periscope-patch $(THOM)/Thom.mdl --skin-from $(THOM)/Thom2.mdl --action $(THOM)/ResoluteWalk.act \
		--action $(THOM)/Wave.act -o $@

# ... and its self-shadowing: the character scene finds out/thom.pao beside out/thom.ppk.
SAMPLE_SHADOW := out/thom.pao
# From the character's pack, whose actions the correction through each action follows.
$(SAMPLE_SHADOW): $(SAMPLE_CHARACTER) $(BUILD)/bin/periscope-shadow
	@mkdir -p $(@D)
	$(BUILD)/bin/periscope-shadow build $(SAMPLE_CHARACTER) -o $@

run: deps
	$(Q)$(MAKE) --no-print-directory all
	$(Q)$(MAKE) --no-print-directory $(SAMPLE_PACK) $(SAMPLE_CHARACTER) $(SAMPLE_SHADOW)
	$(FIRMWARE) --board sim --out out/run

# ---- test and check ----------------------------------------------------------
# `make test`: what a developer runs after every change, in minutes: the gcc
# build, the no-float, layer, self-containment and manual-page checks, the fuzz
# corpora replayed, and every unit, golden, property, tool, desktop-window and
# simulated-board test program, side by side (tests/run_all.sh, -j nproc).
# `make check`: everything, what CI runs: `make test`, then the clang build,
# both sanitizer stages with the fuzz corpora under them, valgrind, and the
# system tests - the VM harness, the packages, the boot images, the
# cross-architecture runs under qemu-user, the Cortex-M run (docs/testing.md).
NPROC := $(shell nproc 2>/dev/null || getconf _NPROCESSORS_ONLN 2>/dev/null || echo 1)
# the builds inside test and check use every processor, unless the caller chose -j
PAR := $(if $(filter -j% --jobserver%,$(MAKEFLAGS)),,-j$(NPROC))
# Test programs that need cross compilers, QEMU, images or packages: `make check` only.
SYSTEM_TEST_NAMES := test_cortex_m test_deb test_deploy test_portability test_vm test_vm_gpiod2
SYSTEM_TESTS := $(filter $(SYSTEM_TEST_NAMES:%=$(BUILD)/tests/%),$(TESTS))
QUICK_TESTS := $(filter-out $(SYSTEM_TESTS),$(TESTS))

test: deps
	$(Q)$(MAKE) $(PAR) --no-print-directory all $(QUICK_TESTS) $(SAMPLE_PACK) $(SAMPLE_CHARACTER) $(SAMPLE_SHADOW) fuzz-replay-build
	$(Q)$(MAKE) --no-print-directory check-self-contained check-core-nofloat check-layers check-architecture \
		check-man-board check-fuzz-corpus
	$(Q)sh tests/run_all.sh $(BUILD) $(QUICK_TESTS)

# CHECK_PRUNE=1 (.ci/run sets it): a stage's own build folder goes once the stage has passed, so that a small
# disk holds the system tests' packages and images without the clang and sanitizer builds beside them (2 GB).
CHECK_PRUNE ?=
check_prune = $(if $(CHECK_PRUNE),rm -rf $(1),true)
check: deps
	$(Q)sh scripts/timed "make test" $(MAKE) --no-print-directory test
	$(Q)sh scripts/timed "clang build" $(MAKE) --no-print-directory check-clang
	$(Q)$(call check_prune,$(BUILD)/clang)
	$(Q)sh scripts/timed "benchmarks' build" $(MAKE) --no-print-directory check-bench-build
	$(Q)sh scripts/timed "sanitizers (gcc)" $(MAKE) --no-print-directory check-sanitize
	$(Q)$(call check_prune,$(SAN_BUILD))
	$(Q)sh scripts/timed "sanitizers (clang)" $(MAKE) --no-print-directory check-sanitize SAN_CC=clang
	$(Q)$(call check_prune,$(BUILD)/sanitize-clang)
	$(Q)sh scripts/timed "valgrind" $(MAKE) --no-print-directory check-memcheck
	$(Q)sh scripts/timed "system tests" $(MAKE) --no-print-directory check-system

.PHONY: system-test-prep
system-test-prep:

# The system tests: what they run on is built first (cross builds for every board with a compiler, the
# native and cross packages, the boot images: mk/cross.mk, mk/deb.mk, mk/image-boot.mk), then they run side by side.
check-system: deps
	$(Q)$(MAKE) $(PAR) --no-print-directory all $(SYSTEM_TESTS)
	$(Q)sh scripts/timed "system tests' builds, packages and images" $(MAKE) --no-print-directory system-test-prep
	$(Q)sh tests/run_all.sh $(BUILD) $(SYSTEM_TESTS)

# A clone with nothing beside it: no file reaches outside the repository, every test data file has its origin
# and licence (scripts/check-self-contained; its self-test proves both checks refuse).
check-self-contained:
	@echo "  CHECK   the repository is self-contained: nothing read from outside it, test data with its sources"
	$(Q)sh scripts/check-self-contained
	$(Q)sh scripts/check-self-contained --self-test >/dev/null

# The unit and fuzz-loop tests again, and the fuzz corpora replayed (mk/fuzz.mk), built with
# AddressSanitizer and UBSan (part of `make check`): any
# out-of-bounds access, use after free, leak or undefined behaviour fails the run (-fno-sanitize-recover).
# Leaks inside third-party libraries are suppressed by name (tests/sanitize/lsan.supp). SAN_CC=clang for clang's.
SAN_CC ?= $(CC)
SAN_BUILD := $(BUILD)/sanitize-$(notdir $(SAN_CC))
SAN_FLAGS := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
SAN_TESTS := $(addprefix $(SAN_BUILD)/tests/,test_3d_abuffer test_3d_area test_3d_place test_envmap_light test_pano_objects test_scene_objects test_3d_threads test_3d_translucent test_morph test_3d_golden test_3d_mesh test_3d_raster \
	test_accuracy test_bands test_config_fuzz test_crc32 test_dither test_envmap test_firmware test_fisheye \
	test_evdev test_fixed test_golden test_hid test_image_io test_image_rows test_input test_io_atomic test_kiosk test_lut test_mip test_pack test_patch \
	test_pixel test_pose test_proxy test_proxy_render test_shadow test_simd test_sky565 test_tiles test_gestures test_log \
	test_open_image)
check-sanitize: deps
	$(Q)$(MAKE) $(PAR) --no-print-directory CC=$(SAN_CC) BUILD=$(SAN_BUILD) OPT="-O1 -g" CFLAGS="$(SAN_FLAGS)" \
		LDFLAGS="-fsanitize=address,undefined" all $(SAN_TESTS) fuzz-replay-build
	$(Q)ASAN_OPTIONS=detect_leaks=1:abort_on_error=0 UBSAN_OPTIONS=print_stacktrace=1 \
		LSAN_OPTIONS=suppressions=$(CURDIR)/tests/sanitize/lsan.supp sh tests/run_all.sh $(SAN_BUILD) $(SAN_TESTS)
	$(Q)$(MAKE) --no-print-directory CC=$(SAN_CC) BUILD=$(SAN_BUILD) OPT="-O1 -g" CFLAGS="$(SAN_FLAGS)" \
		LDFLAGS="-fsanitize=address,undefined" check-fuzz-corpus

# valgrind's memcheck over the device program on the simulated board (part of `make check`): the
# panorama while the tour turns and zooms it, then Thom's patch character; an invalid read or write,
# a use of uninitialised memory, or a block definitely or indirectly lost fails the run.
MEMCHECK := valgrind -q --error-exitcode=99 --leak-check=full --show-leak-kinds=definite,indirect \
	--errors-for-leak-kinds=definite,indirect
check-memcheck: all $(SAMPLE_PACK) $(SAMPLE_CHARACTER) $(SAMPLE_SHADOW) $(SAMPLE_TILED) $(BUILD)/tests/test_tiles
	@echo "  CHECK   valgrind memcheck: the device program, a panorama, a tiled one and a character on the sim board"
	$(Q)$(MEMCHECK) $(FIRMWARE) --board sim --frames-every 0 --max-frames 90 --quiet
	$(Q)$(MEMCHECK) $(FIRMWARE) --board sim --scene $(SAMPLE_TILED) --frames-every 0 --max-frames 60 --quiet
	$(Q)$(MEMCHECK) $(FIRMWARE) --board sim --scene $(SAMPLE_CHARACTER) --frames-every 0 --max-frames 20 --quiet
	@echo "  CHECK   valgrind helgrind: the tile loader thread, raw and JPEG tiles, while frames are drawn (test_tiles)"
	$(Q)PSC_TILES_ONLY='*loader*' valgrind -q --tool=helgrind --error-exitcode=99 \
		$(BUILD)/tests/test_tiles > /dev/null

# A long run of the device program on the simulated board (tests/test_soak.c): 10^5 frames of a tour
# through attract mode, hotspots, scene switches and a gamepad pulled out and back; asserts not one
# allocation after start-up and prints the frame-time distribution. `make test` runs 3000 frames.
SOAK_FRAMES ?= 100000
soak: deps
	$(Q)$(MAKE) --no-print-directory all $(BUILD)/tests/test_soak $(SAMPLE_CHARACTER) $(SAMPLE_SHADOW)
	$(Q)PSC_SOAK_FRAMES=$(SOAK_FRAMES) sh tests/run_all.sh $(BUILD) $(BUILD)/tests/test_soak

# Only the VM cases (part of `make check`): the real backends against real drivers under QEMU.
vm-test: all
	$(Q)sh tests/vm/run.sh --build $(BUILD)

# core must not use floating point (scripts/check-core-nofloat): scalar
# sources compile with the FPU registers taken away (x86-64
# -mgeneral-regs-only), the vector kernels' objects are disassembled and
# refused if they hold a floating-point instruction, and no file names float,
# double or a hosted header. The self-test proves each check can fail.
check-core-nofloat:
	@echo "  CHECK   core/ has no floating point (-mgeneral-regs-only; vector kernels disassembled)"
	$(Q)sh scripts/check-core-nofloat --cc $(CC) $(CORE_SRC) $(wildcard core/*/*.h)
	$(Q)sh scripts/check-core-nofloat --cc $(CC) --self-test >/dev/null

# Dependencies point one way (README.md, "Layout"): every #include of core/,
# io/, hal/, firmware/ and host_tools/ against the table in scripts/check-layers,
# resolved by the compiler with each layer's include paths; the self-test
# proves the check refuses a breach of each kind.
# The device program must also link none of the host tools' code: no symbol
# defined in libpsc_hosttools.a may be defined in periscope.
check-layers: $(FIRMWARE) $(HOST_LIB)
	@echo "  CHECK   layers: each folder includes only what its layer may"
	$(Q)sh scripts/check-layers --cc $(CC)
	$(Q)sh scripts/check-layers --cc $(CC) --self-test >/dev/null
	@echo "  CHECK   $(FIRMWARE) links no host-tool code"
	$(Q)$(NM) -g --defined-only $(HOST_LIB) | awk 'NF == 3 { print $$3 }' | sort -u >$(BUILD)/hosttools.syms
	$(Q)$(NM) --defined-only $(FIRMWARE) | awk 'NF == 3 { print $$3 }' | sort -u | \
		comm -12 - $(BUILD)/hosttools.syms >$(BUILD)/firmware-hosttools.syms
	$(Q)if [ -s $(BUILD)/firmware-hosttools.syms ]; then \
		echo "check-layers: $(FIRMWARE) contains host-tool code:"; cat $(BUILD)/firmware-hosttools.syms; exit 1; fi

# docs/architecture.md names every program, scene kind and operation, render mode, host-library folder and
# header (scripts/check-architecture; its self-test proves it refuses a page missing one of each).
check-architecture:
	@echo "  CHECK   docs/architecture.md names every program, scene kind, render mode and host-library part"
	$(Q)sh scripts/check-architecture
	$(Q)sh scripts/check-architecture --self-test >/dev/null

# Everything (tests included) must also build warning-free with clang.
check-clang:
	@echo "  CHECK   the whole tree builds with clang -Werror"
	$(Q)$(MAKE) $(PAR) --no-print-directory CC=clang BUILD=$(BUILD)/clang all $(patsubst $(BUILD)/%,$(BUILD)/clang/%,$(TESTS))

# ---- bench: speed, always side by side with a reference in the same run ------
# Not part of `make test` or `make check` (no timing in tests). Each bench/<name>/ folder is one
# program build/bench/<name> from its .c and .cpp files; its extra libraries
# come from bench/<name>/pkg-config (pkg-config module names, one line).
# bench/packages.txt lists the Debian packages the benchmarks need.
CXX ?= $(CROSS_COMPILE)g++
ifeq ($(origin CXX),default)
CXX := $(CROSS_COMPILE)g++
endif
# bench/common/ is what the benchmarks share (linked into each, included as "common/NAME.h").
BENCH_DIRS := $(filter-out bench/common,$(sort $(patsubst %/,%,$(dir $(wildcard bench/*/*.c bench/*/*.cpp)))))
BENCH_PROGS := $(patsubst bench/%,$(BUILD)/bench/%,$(BENCH_DIRS))
BENCH_COMMON_OBJS := $(call obj,$(wildcard bench/common/*.c))
$(BUILD)/obj/bench/%.o: TEST_INC += -Ibench
# the gigapixel bench writes its panorama with the tests' generator (tests/support/tsup_panorama.c: libjpeg only)
$(BUILD)/bench/tiles: $(BUILD)/lib/libpsc_testsupport.a
BENCH_PACKAGES = $(shell cat bench/packages.txt 2>/dev/null)
bench_pkgs = $(shell cat bench/$(1)/pkg-config 2>/dev/null)

$(BUILD)/obj/bench/%.o: bench/%.cpp
	@mkdir -p $(@D)
	@$(if $(Q),echo "  CXX     $<")
	$(Q)$(CXX) -std=c++17 -O2 -g -MMD -MP -Wall -Wextra -Werror -Icore -Iio -Ihost_tools/lib -Ibench $(shell $(PKG_CONFIG) --cflags $(call bench_pkgs,$(firstword $(subst /, ,$*))) 2>/dev/null) -c $< -o $@

.SECONDEXPANSION:
$(BUILD)/bench/%: $$(addprefix $(BUILD)/obj/,$$(addsuffix .o,$$(basename $$(wildcard bench/$$*/*.c bench/$$*/*.cpp)))) \
		$(BENCH_COMMON_OBJS) $(HOST_LIB) $(IO_LIB) $(CORE_LIB)
	@mkdir -p $(@D)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(if $(wildcard bench/$*/*.cpp),$(CXX),$(CC)) $(LDFLAGS) -o $@ $^ $(shell $(PKG_CONFIG) --libs $(call bench_pkgs,$*) 2>/dev/null) $(IMG_LIBS) $(LDLIBS_HOST)

bench:
	$(Q)sh scripts/install-deps.sh $(BENCH_PACKAGES)
	$(Q)$(MAKE) --no-print-directory all $(BENCH_PROGS)
	$(Q)mkdir -p bench/results
	$(Q)for b in $(BENCH_PROGS); do echo "==== $$b"; $$b --out bench/results || exit 1; done

# The benchmarks built, not run (part of `make check`: a change to an interface must not leave `make bench`
# broken until someone runs it).
check-bench-build:
	$(Q)sh scripts/install-deps.sh $(BENCH_PACKAGES)
	@echo "  CHECK   the benchmarks build: $(notdir $(BENCH_PROGS))"
	$(Q)$(MAKE) $(PAR) --no-print-directory all $(BENCH_PROGS)

# Instruction counts (repeatable on a noisy machine): each bench program's --callgrind mode under valgrind.
bench-callgrind:
	$(Q)sh scripts/install-deps.sh valgrind $(BENCH_PACKAGES)
	$(Q)$(MAKE) --no-print-directory all $(BENCH_PROGS)
	$(Q)mkdir -p bench/results
	$(Q)for b in $(BENCH_PROGS); do echo "==== $$b"; $$b --callgrind --out bench/results || exit 1; done

install: all
	install -d $(DESTDIR)$(PREFIX)/bin
	install -m 755 $(FIRMWARE) $(TOOLS) $(DESTDIR)$(PREFIX)/bin/

clean:
	rm -rf $(BUILD) out
