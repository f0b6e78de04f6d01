# The bootable kiosk image of a Linux board (issue 6, "Deployment images"):
#   make boot-image BOARD=rpi-arm64   the cross build, then scripts/boot-image:
#                                     build/rpi-arm64/image/{vmlinuz,initramfs.cpio.gz,README}
# `make test` makes the rpi-arm64 image when qemu-system-aarch64 and the
# cross compiler are there, and tests/test_boot_arm64.c boots it
# (tests/image/boot-arm64.sh). When this machine cannot make it (no arm64
# libraries, no apt architecture, no download) the reason is kept in
# build/rpi-arm64/image.why and the boot test is skipped saying so.

.PHONY: boot-image boot-image-test-prep

boot-image:
	$(if $(BOARD),,$(error boot-image: name the board: make boot-image BOARD=<board> (one of: $(CROSS_BOARDS))))
	$(call cross_make,$(BOARD),)
	$(Q)$(MAKE) --no-print-directory $(BUILD)/bin/periscope-pack
	$(Q)sh scripts/boot-image $(BOARD)

# after portability-builds: both build into build/rpi-arm64/
test: boot-image-test-prep
boot-image-test-prep: deps portability-builds
	+$(Q)if [ -n "$$PSC_VM_SKIP" ]; then exit 0; fi; \
	if ! command -v qemu-system-aarch64 >/dev/null 2>&1 || ! command -v aarch64-linux-gnu-gcc >/dev/null 2>&1; then exit 0; fi; \
	mkdir -p build/rpi-arm64; rm -f build/rpi-arm64/image.why; \
	if ! $(MAKE) --no-print-directory boot-image BOARD=rpi-arm64; then \
		[ -s build/rpi-arm64/image.why ] || { echo "boot-image: failed (above)"; exit 1; }; \
		echo "boot-image: not made, the boot test will be skipped: $$(cat build/rpi-arm64/image.why)"; \
	fi

# `make image BOARD=…` gives both deliverables: the .deb (mk/deb.mk) and the bootable image.
image: boot-image
