# SPDX-License-Identifier: MIT
# Cross builds for Linux boards (boards/README.md, "Cross builds").
#   make BOARD=rpi-arm64          firmware, host tools and core into build/rpi-arm64/
#   make cross BOARD=rpi-armhf    the same, by name
#   make cross-all                every board whose board.conf names a debian_arch
# The board's `toolchain = PREFIX-` and `debian_arch = ARCH` lines pick the
# compiler (PREFIXgcc) and the target's libraries: Debian multiarch
# (/usr/lib/<triplet>), or else the sysroot build/sysroot/ARCH
# (scripts/cross-env decides, scripts/cross-deps installs either). Without the target's image libraries (libpng, libjpeg, zlib) only core
# and psc-render-raw are built; without its device libraries (libdrm, libusb,
# SDL2, libgpiod, libevdev) not the firmware. Each case is said, not silent.
# A board without debian_arch (a microcontroller) is not handled here.
# The cross build is a sub-make with BUILD, CROSS_COMPILE and PKG_CONFIG set
# (and HAL_BACKENDS from the board's `backends` line), so the rules of the
# Makefile serve it unchanged. What it builds is what a device runs: it is
# hardened the way Debian builds its packages (dpkg-buildflags with
# hardening=+all: fortified libc calls, stack protector, full RELRO).

.PHONY: cross cross-all portability-builds $(addprefix cross-board-,$(CROSS_BOARDS))

# A board's key, read by the device's own reader of board files (scripts/board-key).
board_key = $(shell sh scripts/board-key $(1) $(2))
CROSS_BOARDS := $(sort $(foreach c,$(wildcard boards/*/board.conf),\
	$(if $(call board_key,$(notdir $(patsubst %/,%,$(dir $(c)))),debian_arch),$(notdir $(patsubst %/,%,$(dir $(c)))))))

# psc-render-raw: core and libc only, linked statically (runs under qemu-user
# with no target libraries): the probe of tests/portability/run.sh.
PORT_RENDER := $(BUILD)/portability/psc-render-raw
$(PORT_RENDER): $(BUILD)/obj/tests/portability/psc_render_raw.o $(CORE_LIB)
	@mkdir -p $(@D)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) $(LDFLAGS) -static -o $@ $^

# $(call cross_make,BOARD,GOALS): GOALS of the sub-make for BOARD, or the most
# of them its libraries allow. Fails if the board's compiler is missing.
define cross_make
	+$(Q)b='$(1)'; env=$$(sh scripts/cross-env $$b) || exit 2; eval "$$env"; \
	prefix=$$CROSS_PREFIX; arch=$$DEB_ARCH; pc=$$TARGET_PKG_CONFIG; \
	if ! command -v "$${prefix}gcc" >/dev/null 2>&1; then \
		echo "cross: $$b: no $${prefix}gcc (sh scripts/cross-deps $$b installs it)"; exit 1; fi; \
	libs="Debian multiarch"; [ -z "$$SYSROOT" ] || libs="sysroot $${SYSROOT#$(CURDIR)/}"; \
	goals="$(2)"; \
	if [ -z "$$goals" ]; then \
		if ! $$pc --exists $(IMG_PKGS); then \
			echo "cross: $$b: no $(IMG_PKGS) for $$arch (sh scripts/cross-deps $$b): building core and psc-render-raw only"; \
			goals="build/$$b/lib/libpsc_core.a build/$$b/portability/psc-render-raw"; \
		elif ! $$pc --exists $(HAL_PKGS); then \
			echo "cross: $$b: no $(HAL_PKGS) for $$arch: building core and the host tools, not the firmware"; \
			goals="build/$$b/lib/libpsc_core.a $(patsubst $(BUILD)/%,build/$$b/%,$(TOOLS)) build/$$b/portability/psc-render-raw"; \
		else \
			goals="all build/$$b/portability/psc-render-raw"; \
		fi; \
	fi; \
	hard=""; if command -v dpkg-buildflags >/dev/null 2>&1; then \
		bf="env DEB_BUILD_MAINT_OPTIONS=hardening=+all DEB_HOST_ARCH=$$arch dpkg-buildflags --get"; \
		hard="$$($$bf CPPFLAGS) $$($$bf CFLAGS)"; hard_ld=$$($$bf LDFLAGS); fi; \
	echo "  CROSS   $$b ($${prefix}gcc, $$arch, libraries: $$libs) -> build/$$b/"; \
	$(MAKE) $(PAR) --no-print-directory PSC_CROSS_INNER=1 BOARD=$$b BUILD=build/$$b CROSS_COMPILE=$$prefix \
		CC="$$TARGET_CC" AR=$${prefix}ar PKG_CONFIG="$$pc" $${HAL_BACKENDS:+HAL_BACKENDS="$$HAL_BACKENDS"} \
		CFLAGS="$$hard $(CFLAGS)" LDFLAGS="$$hard_ld $(LDFLAGS)" $$goals
endef

cross:
	$(if $(BOARD),,$(error cross: name the board: make cross BOARD=<board> (one of: $(CROSS_BOARDS))))
	$(call cross_make,$(BOARD),)

cross-all: $(addprefix cross-board-,$(CROSS_BOARDS))
cross-board-%:
	$(call cross_make,$*,)

# `make BOARD=<a Linux board>` alone means the cross build.
ifneq ($(BOARD),)
ifeq ($(PSC_CROSS_INNER),)
ifneq ($(call board_key,$(BOARD),debian_arch),)
.DEFAULT_GOAL := cross
endif
endif
endif

# `make check`: the native probe, and the probe and periscope-render for every
# board whose compiler is installed (tests/test_portability.c runs them under
# qemu-user; a missing compiler or library is reported there as a skip).
system-test-prep: portability-builds
portability-builds: deps
	$(Q)$(MAKE) --no-print-directory $(PORT_RENDER) $(BUILD)/bin/periscope-render
	+$(Q)for b in $(CROSS_BOARDS); do \
		prefix=$$(sh scripts/board-key $$b toolchain); \
		command -v "$${prefix}gcc" >/dev/null 2>&1 || continue; \
		$(MAKE) --no-print-directory PSC_CROSS_INNER=1 BUILD=$(BUILD) cross-probe-$$b || exit 1; \
	done

# the probe, and periscope-render where the target has the image libraries
cross-probe-%:
	$(call cross_make,$*,build/$*/portability/psc-render-raw \
		$$($$pc --exists $(IMG_PKGS) && echo build/$*/bin/periscope-render))
