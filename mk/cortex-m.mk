# SPDX-License-Identifier: MIT
# mk/cortex-m.mk - bare-metal microcontroller boards: `make BOARD=cortex-m7`.
#
# A board whose boards/<name>/board.conf says `build = core-only` gets the
# integer core alone, cross-built with its `toolchain` (arm-none-eabi-) for its
# `cpu` with `float_abi` (soft) into build/<name>/:
#   libpsc_core.a       every core/*.c
#   cm_test.elf         tests/mcu/cm_main.c: one view rendered from a tiny scene
#                       pack in flash (the bundled panorama scaled to 256x128 by
#                       tests/mcu/mkscene.c and packed by periscope-pack on the
#                       host, linked in with objcopy) into a static frame through
#                       a static workspace; linker script tests/mcu/cortex-m.ld
#                       with the board's memory map (memory.ld)
# then prints flash and RAM use and fails if a floating-point helper or a
# libc allocator is linked (tests/mcu/check-symbols.sh on the image and on
# every core object), and proves that check can fail by linking deliberately
# bad objects (selftest-float.elf, selftest-alloc.elf) that it must reject.
#   make BOARD=cortex-m7            build, size, symbol check and its self-test (target mcu)
#   make BOARD=cortex-m7 mcu-run    also run it under qemu-system-arm (board's qemu_machine,
#                                   semihosting) -> build/<name>/qemu.log, and render the same
#                                   view on the host -> build/<name>/host-view.png
# tests/test_cortex_m.c runs both from `make check` and compares the frames byte for byte.
# Toolchain on Debian: apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi (qemu-system-arm to run it).

CM_CONF := $(if $(BOARD),$(wildcard boards/$(BOARD)/board.conf))
cm_key = $(strip $(shell sh scripts/board-key $(CM_CONF) $(1)))
CM_BOARD := $(if $(CM_CONF),$(if $(filter core-only,$(call cm_key,build)),$(BOARD)))

.PHONY: mcu mcu-run cm-host-tools

ifeq ($(CM_BOARD),)
mcu mcu-run:
	@echo "$@: BOARD=$(BOARD) is not a microcontroller board (boards/<name>/board.conf with 'build = core-only'), e.g. make BOARD=cortex-m7" >&2
	@exit 2
else
.DEFAULT_GOAL := mcu

CM_ROOT ?= build
CM_OUT := $(CM_ROOT)/$(CM_BOARD)
# the host build whose tools make the scene (the usual one; not this board's)
CM_HOST_BUILD ?= build
CM_HOSTCC ?= cc
CM_PREFIX := $(call cm_key,toolchain)
CM_CC := $(CM_PREFIX)gcc
CM_AR := $(CM_PREFIX)ar
CM_NM := $(CM_PREFIX)nm
CM_SIZE := $(CM_PREFIX)size
CM_OBJCOPY := $(CM_PREFIX)objcopy
CM_ARCH := -mcpu=$(call cm_key,cpu) -mthumb -mfloat-abi=$(call cm_key,float_abi)
CM_CFLAGS := -std=c11 $(WARN) -O2 -g -MMD -MP -ffreestanding -fno-common -ffunction-sections -fdata-sections \
	$(CM_ARCH) -Icore
# no start files (cm_main.c has the vector table and reset handler); newlib-nano
# only for what the compiler itself calls (memcpy, memset), libnosys stubs.
CM_LDFLAGS := $(CM_ARCH) -nostartfiles --specs=nano.specs --specs=nosys.specs -T tests/mcu/cortex-m.ld -L$(CM_OUT) \
	-Wl,--gc-sections -Wl,--no-warn-rwx-segments
CM_CHECK := sh tests/mcu/check-symbols.sh $(CM_NM)

CM_CORE_OBJ := $(patsubst %.c,$(CM_OUT)/obj/%.o,$(CORE_SRC))
CM_LIB := $(CM_OUT)/libpsc_core.a
CM_ELF := $(CM_OUT)/cm_test.elf
CM_SCENE_SRC := assets/pannellum-examplepano.jpg
CM_DISPLAY := $(or $(call cm_key,display_size),64x48)
CM_SCENE_SIZE := 256 128

mcu: $(CM_ELF) $(CM_OUT)/selftest-float.elf $(CM_OUT)/selftest-alloc.elf
	@echo "  SIZE    $(CM_ELF) ($(CM_BOARD): flash $(call cm_key,flash_size), RAM $(call cm_key,ram_size))"
	$(Q)$(CM_SIZE) $(CM_ELF)
	$(Q)$(CM_SIZE) $(CM_ELF) | awk -v scene=$$(wc -c < $(CM_OUT)/scene.pano) -v stack=$(call cm_key,stack_size) \
		'NR == 2 { printf "  %s: flash %d bytes (text+data; %d of them the scene pack, %d code and constants), RAM %d bytes (data+bss) + stack %s\n", \
		"$(CM_BOARD)", $$1 + $$2, scene, $$1 + $$2 - scene, $$2 + $$3, stack }'
	$(Q)$(CM_SIZE) -t $(CM_LIB) | awk 'END { printf "  core/ alone (all of libpsc_core.a, before --gc-sections): text %d, data %d, bss %d bytes\n", $$1, $$2, $$3 }'
	@echo "  CHECK   no floating-point helper or heap allocation linked ($(CM_NM))"
	$(Q)$(CM_CHECK) $(CM_ELF) $(CM_CORE_OBJ)
	$(Q)for t in float alloc; do \
		if $(CM_CHECK) $(CM_OUT)/selftest-$$t.elf >$(CM_OUT)/selftest-$$t.log 2>&1; then \
			echo "mcu: the symbol check itself is broken: it accepted $(CM_OUT)/selftest-$$t.elf"; exit 1; fi; \
		echo "  CHECK   self-test: the check rejects a deliberately bad image: $$(cat $(CM_OUT)/selftest-$$t.log)"; done

mcu-run: mcu cm-host-tools
	@command -v qemu-system-arm >/dev/null 2>&1 || { echo "mcu-run: qemu-system-arm is not installed (apt-get install qemu-system-arm)" >&2; exit 1; }
	@echo "  QEMU    $(CM_ELF) on -M $(call cm_key,qemu_machine)"
	$(Q)rm -f $(CM_OUT)/qemu.log
	$(Q)timeout 120 qemu-system-arm -M $(call cm_key,qemu_machine) -nographic -monitor none -serial none \
		-semihosting-config enable=on,target=native -kernel $(CM_ELF) >$(CM_OUT)/qemu.log 2>&1; \
		rc=$$?; grep -v '^frame ' $(CM_OUT)/qemu.log; [ $$rc -eq 0 ] || { echo "mcu-run: qemu-system-arm exited with $$rc"; exit 1; }
	$(Q)$(CM_HOST_BUILD)/bin/periscope-render $(CM_OUT)/scene.pano $$(sed -n 's/^#define CM_VIEW_RENDER_ARGS "\(.*\)"/\1/p' tests/mcu/cm_view.h) \
		-o $(CM_OUT)/host-view.png

# ---- the cross-built objects ----
$(CM_OUT)/obj/%.o: %.c
	@command -v $(CM_CC) >/dev/null 2>&1 || { echo "mcu: $(CM_CC) is not installed (Debian: apt-get install gcc-arm-none-eabi libnewlib-arm-none-eabi)" >&2; exit 1; }
	@mkdir -p $(@D)
	@$(if $(Q),echo "  CC      $< ($(CM_BOARD))")
	$(Q)$(CM_CC) $(CM_CFLAGS) -c $< -o $@

$(CM_LIB): $(CM_CORE_OBJ)
	@$(if $(Q),echo "  AR      $@")
	$(Q)rm -f $@ && $(CM_AR) rcs $@ $^

$(CM_OUT)/memory.ld: $(CM_CONF) mk/cortex-m.mk
	@mkdir -p $(@D)
	$(Q)printf '/* from %s by mk/cortex-m.mk */\nMEMORY\n{\n    FLASH (rx) : ORIGIN = %s, LENGTH = %s\n    RAM (rwx) : ORIGIN = %s, LENGTH = %s\n}\n_stack_size = %s;\n' \
		$(CM_CONF) $(call cm_key,flash_origin) $(call cm_key,flash_size) $(call cm_key,ram_origin) \
		$(call cm_key,ram_size) $(call cm_key,stack_size) >$@

# ---- the scene: made on the host, linked in as read-only data ----
cm-host-tools:
	$(Q)$(MAKE) -s --no-print-directory BOARD= CROSS_COMPILE= BUILD=$(CM_HOST_BUILD) \
		$(CM_HOST_BUILD)/bin/periscope-pack $(CM_HOST_BUILD)/bin/periscope-render \
		$(CM_HOST_BUILD)/lib/libpsc_hosttools.a $(CM_HOST_BUILD)/lib/libpsc_io.a $(CM_HOST_BUILD)/lib/libpsc_core.a

$(CM_OUT)/host/mkscene: tests/mcu/mkscene.c | cm-host-tools
	@mkdir -p $(@D)
	@$(if $(Q),echo "  HOSTCC  $@")
	$(Q)$(CM_HOSTCC) $(BASE_CFLAGS) $(HOSTED_DEFS) $(TOOLS_INC) $(IMG_CFLAGS) $< -o $@ \
		$(CM_HOST_BUILD)/lib/libpsc_hosttools.a $(CM_HOST_BUILD)/lib/libpsc_io.a $(CM_HOST_BUILD)/lib/libpsc_core.a \
		$(IMG_LIBS) $(LDLIBS_HOST)

$(CM_OUT)/scene.pano: $(CM_SCENE_SRC) $(CM_OUT)/host/mkscene $(CM_CONF) | cm-host-tools
	$(Q)$(CM_OUT)/host/mkscene $(CM_SCENE_SRC) $(CM_OUT)/scene.png $(CM_SCENE_SIZE)
	$(Q)$(CM_HOST_BUILD)/bin/periscope-pack $(CM_OUT)/scene.png -o $@ --display $(CM_DISPLAY) \
		--format $(or $(call cm_key,display_format),rgb565) --levels 1 --quiet

# objcopy names the symbols after the file: _binary_scene_pano_start/_end
$(CM_OUT)/scene.o: $(CM_OUT)/scene.pano
	$(Q)cd $(CM_OUT) && $(CM_OBJCOPY) -I binary -O elf32-littlearm -B arm \
		--rename-section .data=.rodata.scene,alloc,load,readonly,data,contents \
		--set-section-alignment .data=8 scene.pano scene.o

# ---- the images ----
CM_LINK_DEPS := $(CM_OUT)/obj/tests/mcu/cm_main.o $(CM_OUT)/scene.o $(CM_LIB) $(CM_OUT)/memory.ld tests/mcu/cortex-m.ld

$(CM_ELF): $(CM_LINK_DEPS)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CM_CC) $(CM_LDFLAGS) -Wl,-Map=$(CM_OUT)/cm_test.map -o $@ $(filter %.o %.a,$^)

# the check's self-test: the same image plus a function that multiplies a
# double / calls malloc (kept by -u despite --gc-sections)
$(CM_OUT)/selftest-float.c:
	@mkdir -p $(@D)
	$(Q)printf 'double cm_selftest_bad(double x);\ndouble cm_selftest_bad(double x) { return x * 0.5 + 1.0; }\n' >$@
$(CM_OUT)/selftest-alloc.c:
	@mkdir -p $(@D)
	$(Q)printf '#include <stdlib.h>\nvoid *cm_selftest_bad(size_t n);\nvoid *cm_selftest_bad(size_t n) { return malloc(n); }\n' >$@
$(CM_OUT)/selftest-%.o: $(CM_OUT)/selftest-%.c
	$(Q)$(CM_CC) $(CM_CFLAGS) -c $< -o $@
$(CM_OUT)/selftest-%.elf: $(CM_OUT)/selftest-%.o $(CM_LINK_DEPS)
	$(Q)$(CM_CC) $(CM_LDFLAGS) -Wl,-u,cm_selftest_bad -o $@ $(filter %.o %.a,$^)

-include $(shell find $(CM_OUT)/obj -name '*.d' 2>/dev/null)
endif
