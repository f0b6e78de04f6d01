# SPDX-License-Identifier: MIT
# The bootable kiosk image of a Linux board (issue 6, "Deployment images"):
#   make boot-image BOARD=rpi-arm64   the cross build, then scripts/boot-image:
#                                     build/rpi-arm64/image/{vmlinuz,initramfs.cpio.gz,README}
#                                     and, with `image.disk = raspi|efi`, the
#                                     bootable disk periscope-rpi-arm64.img
# `make check` makes the image of every board with an `image.kernel` key
# (rpi-arm64, rpi-armhf) whose cross compiler is there, and
# tests/test_deploy.c checks the SD card and boots the images
# (tests/image/). When this machine cannot make one (no target libraries, no
# download) the reason is kept in build/BOARD/image.why and its tests are
# skipped saying so.

.PHONY: boot-image boot-image-test-prep

# what scripts/boot-image and scripts/disk-image run on the host
IMAGE_PACKAGES := cpio kmod dosfstools mtools fdisk
# the boards with a deployment image
IMAGE_BOARDS := $(sort $(foreach b,$(CROSS_BOARDS),$(if $(call board_key,$(b),image.kernel),$(b))))

boot-image:
	$(if $(BOARD),,$(error boot-image: name the board: make boot-image BOARD=<board> (one of: $(CROSS_BOARDS))))
	$(call cross_make,$(BOARD),)
	$(Q)$(MAKE) --no-print-directory $(BUILD)/bin/periscope-pack
	$(Q)sh scripts/install-deps.sh $(IMAGE_PACKAGES)
	$(Q)sh scripts/boot-image $(BOARD)

# after portability-builds: both build into build/<board>/
system-test-prep: boot-image-test-prep
boot-image-test-prep: deps portability-builds
	+$(Q)if [ -n "$$PSC_VM_SKIP" ]; then exit 0; fi; \
	for b in $(IMAGE_BOARDS); do \
		env=$$(sh scripts/cross-env $$b) || exit 1; eval "$$env"; \
		command -v "$${CROSS_PREFIX}gcc" >/dev/null 2>&1 || continue; \
		mkdir -p build/$$b; rm -f build/$$b/image.why; \
		if ! $(MAKE) --no-print-directory boot-image BOARD=$$b; then \
			[ -s build/$$b/image.why ] || { echo "boot-image: $$b failed (above)"; exit 1; }; \
			echo "boot-image: $$b not made, its boot tests will be skipped: $$(cat build/$$b/image.why)"; \
		fi; \
	done

# `make image BOARD=…` gives both deliverables: the .deb (mk/deb.mk) and the bootable image.
image: boot-image
