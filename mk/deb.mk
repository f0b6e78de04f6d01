# SPDX-License-Identifier: MIT
# Debian packages (README.md, "Deploying to a Raspberry Pi"; packaging/deb/).
#   make image BOARD=rpi-arm64    cross-builds (mk/cross.mk) and packages
#                                 build/rpi-arm64/periscope_<ver>_arm64.deb
#   make deb BOARD=...            the package alone (`image` also makes the
#                                 bootable image where mk/image-boot.mk adds it)
#   make deb-lintian BOARD=...    the package, then lintian on it
# The version is the VERSION file's. The sample scene is packed for the
# board's display_size and display_format by the host's periscope-pack (a pack
# is the same on every architecture) into $(BUILD)/scenes/<board>.pano.
# scripts/build-deb assembles the package; a board whose target libraries are
# not installed (its cross build is core only) stops with the reason. The
# programs it packages are the build's list, BUILD/programs.txt (the
# Makefile's PROGRAMS, written by `make all`): $(BUILD)/programs.txt for the
# native package, build/<board>/programs.txt for a cross build's.
# `make check` builds the package of the native board (x86-kiosk on amd64) from
# this build's binaries into $(BUILD)/deb/; tests/test_deb.c checks it.

.PHONY: image deb deb-lintian deb-test-package deb-cross-test-packages check-man-board check-man-pages

DEB_VERSION := $(shell tr -d ' \n' < VERSION 2>/dev/null)
DEB_SAMPLE_JPG := assets/pannellum-examplepano.jpg
DEB_INPUTS := VERSION scripts/build-deb $(wildcard packaging/deb/* packaging/man/*.1 packaging/man/*.5) assets/ATTRIBUTION.md
DEB_HOST_ARCH := $(shell dpkg --print-architecture 2>/dev/null)
# the board built natively for `make check`: x86-kiosk on amd64, else the first of that architecture
DEB_HOST_BOARD := $(firstword $(foreach b,x86-kiosk $(filter-out x86-kiosk,$(CROSS_BOARDS)),\
	$(if $(filter $(DEB_HOST_ARCH),$(call board_key,$(b),debian_arch)),$(b))))

# the sample scene for a board's display (any build's periscope-pack will do)
$(BUILD)/scenes/%.pano: $(DEB_SAMPLE_JPG) $(BUILD)/bin/periscope-pack boards/%/board.conf
	@mkdir -p $(@D)
	@$(if $(Q),echo "  PACK    $@")
	$(Q)size='$(call board_key,$*,display_size)'; fmt=$$(sh scripts/board-pack-format $*); \
	[ -n "$$size" ] || { echo "deb: boards/$*/board.conf has no display_size"; exit 1; }; \
	$(BUILD)/bin/periscope-pack $(DEB_SAMPLE_JPG) -o $@ --display $$size --format $$fmt --quiet

image: deb

deb:
	$(if $(BOARD),,$(error deb: name the board: make image BOARD=<board> (one of: $(CROSS_BOARDS))))
	$(if $(call board_key,$(BOARD),debian_arch),,$(error deb: boards/$(BOARD)/board.conf names no debian_arch: not a Linux board (one of: $(CROSS_BOARDS))))
	+$(Q)b='$(BOARD)'; env=$$(sh scripts/cross-env $$b) || exit 2; eval "$$env"; \
	prefix=$$CROSS_PREFIX; arch=$$DEB_ARCH; \
	if ! command -v dpkg-deb >/dev/null 2>&1; then echo "deb: no dpkg-deb (apt-get install dpkg-dev)"; exit 1; fi; \
	if ! command -v "$${prefix}gcc" >/dev/null 2>&1; then \
		echo "deb: $$b: no $${prefix}gcc: sh scripts/cross-deps $$b installs the cross toolchain"; exit 1; fi; \
	missing=""; for p in $(sort $(IMG_PKGS) $(HAL_PKGS)); do \
		$$TARGET_PKG_CONFIG --exists $$p || missing="$$missing $$p"; \
	done; \
	if [ -n "$$missing" ]; then \
		echo "deb: $$b: the $$arch libraries$$missing are not installed, so the cross build is core only"; \
		echo "deb: $$b: no package without the firmware: sh scripts/cross-deps $$b installs them (multiarch, or a sysroot)"; \
		exit 1; fi
	+$(Q)$(MAKE) --no-print-directory cross BOARD=$(BOARD)
	+$(Q)$(MAKE) --no-print-directory $(BUILD)/bin/periscope-pack
	+$(Q)$(MAKE) --no-print-directory $(BUILD)/scenes/$(BOARD).pano
	$(Q)rm -f build/$(BOARD)/periscope_*.deb
	$(Q)sh scripts/build-deb --board $(BOARD) --bindir build/$(BOARD)/bin --programs build/$(BOARD)/programs.txt \
		--pack $(BUILD)/scenes/$(BOARD).pano --strip $(call board_key,$(BOARD),toolchain)strip \
		--out build/$(BOARD)/periscope_$(DEB_VERSION)_$(call board_key,$(BOARD),debian_arch).deb

deb-lintian: deb
	$(Q)sh scripts/install-deps.sh lintian
	lintian --info build/$(BOARD)/periscope_$(DEB_VERSION)_$(call board_key,$(BOARD),debian_arch).deb

# ---- make check: the native board's package from this build's binaries ------------
DEB_TEST_PACKAGE := $(if $(DEB_HOST_BOARD),$(BUILD)/deb/periscope_$(DEB_VERSION)_$(DEB_HOST_ARCH).deb)

system-test-prep: deb-test-package
deb-test-package: deps
	+$(Q)if ! command -v dpkg-deb >/dev/null 2>&1 || ! command -v dpkg-shlibdeps >/dev/null 2>&1; then \
		echo "deb: no dpkg-deb or dpkg-shlibdeps (dpkg-dev): no package to test, test_deb skips"; \
	elif [ -z "$(DEB_HOST_BOARD)" ]; then \
		echo "deb: no board has debian_arch = $(DEB_HOST_ARCH): no package to test, test_deb skips"; \
	else \
		$(MAKE) --no-print-directory all && $(MAKE) --no-print-directory $(DEB_TEST_PACKAGE); \
	fi

ifneq ($(DEB_TEST_PACKAGE),)
$(DEB_TEST_PACKAGE): $(FIRMWARE) $(TOOLS) $(PROGRAM_LIST) $(BUILD)/scenes/$(DEB_HOST_BOARD).pano \
		boards/$(DEB_HOST_BOARD)/board.conf $(DEB_INPUTS)
	$(Q)rm -f $(@D)/periscope_*.deb
	$(Q)sh scripts/build-deb --board $(DEB_HOST_BOARD) --bindir $(BUILD)/bin --programs $(PROGRAM_LIST) \
		--pack $(BUILD)/scenes/$(DEB_HOST_BOARD).pano --strip strip --compress gzip --out $@
endif

# ---- make test: the manual pages --------------------------------------------------
# check-man-pages: every program of $(PROGRAM_LIST) has its page packaging/man/NAME.1
# (and every page there a program), naming it, with every option its --help shows,
# rendering without a groff warning (scripts/check-man-pages; its self-test proves
# a missing page, an undocumented option, a warning and a page without a program
# are refused). It reads the programs' --help, so it needs them built.
check-man-pages: $(PROGRAM_LIST) $(FIRMWARE) $(TOOLS)
	@echo "  CHECK   every program in $(PROGRAM_LIST) has a manual page with its options, no groff warnings"
	$(Q)command -v groff >/dev/null 2>&1 || sh scripts/install-deps.sh groff-base
	$(Q)sh scripts/check-man-pages --programs $(PROGRAM_LIST) --bindir $(BUILD)/bin
	$(Q)sh scripts/check-man-pages --self-test >/dev/null

# check-man-board (which `make test` runs; it runs check-man-pages first): the board
# file's manual page, periscope-board(5), documents every key the sources read
# (firmware/board_config.c's key_table, each backend's options, the build and image
# keys) and renders without a groff warning (scripts/check-man-board); the self-test
# proves each omission is refused. tests/test_deb.c runs it again with the page's
# examples on the sim board.
check-man-board: check-man-pages
	@echo "  CHECK   periscope-board(5) documents every board key, renders without warnings"
	$(Q)command -v groff >/dev/null 2>&1 || sh scripts/install-deps.sh groff-base
	$(Q)sh scripts/check-man-board
	$(Q)sh scripts/check-man-board --self-test >/dev/null

# ---- make check: the package of every image board (rpi-arm64, rpi-armhf) ------------
# where its cross compiler and target libraries are there; tests/test_deploy.c
# takes each apart (tests/image/deb-cross.sh) or says why it is skipped.
system-test-prep: deb-cross-test-packages
deb-cross-test-packages: deps portability-builds
	+$(Q)for b in $(IMAGE_BOARDS); do \
		env=$$(sh scripts/cross-env $$b) || exit 1; eval "$$env"; \
		command -v "$${CROSS_PREFIX}gcc" >/dev/null 2>&1 || continue; \
		$$TARGET_PKG_CONFIG --exists $(sort $(IMG_PKGS) $(HAL_PKGS)) || \
			{ echo "deb: $$b: no $$DEB_ARCH libraries: no package to test (sh scripts/cross-deps $$b)"; continue; }; \
		$(MAKE) --no-print-directory deb BOARD=$$b || exit 1; \
	done
