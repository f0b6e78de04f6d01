# SPDX-License-Identifier: MIT
# Coverage-guided fuzzing of every parser with libFuzzer (docs/testing.md, "Fuzzing").
#   make fuzz                 each harness tests/fuzz/fuzz_NAME.c built with clang
#                             -fsanitize=fuzzer,address,undefined into $(FUZZ_DIR)/bin/ and run
#                             FUZZ_SECONDS (60) on a copy of its seed corpus; non-zero on a finding
#   make fuzz-long            each until FUZZ_RUNS executions (10 M) or FUZZ_MAX_SECONDS (7200),
#                             FUZZ_JOBS (1) at a time, niced: $(FUZZ_DIR)/long/NAME.log and summary.txt
#   make fuzz-merge           the inputs of $(FUZZ_DIR)/corpus/NAME that add coverage, into the
#                             tree's tests/fuzz/corpus/NAME (by hand, after a run; review before committing)
#   make check-fuzz-corpus    (part of `make test`, and of `make check` under both sanitizers) every seed
#                             corpus and tests/fuzz/regress/NAME
#                             replayed through the harnesses built with $(CC) by a plain main()
#                             (tests/fuzz/fuzz_replay_main.c) into $(BUILD)/fuzz-replay/
# FUZZ_NAMES=pack,mesh (or space-separated) runs only those harnesses.
# The fuzz build is a build of its own, with the top Makefile's rules and flags for each
# layer: `make BUILD=$(FUZZ_DIR) CC=$(FUZZ_CC)` with the fuzzer's instrumentation in CFLAGS.

.PHONY: fuzz fuzz-long fuzz-merge fuzz-build fuzz-harnesses check-fuzz-corpus

FUZZ_HARNESS_SRC := $(filter-out tests/fuzz/fuzz_support.c tests/fuzz/fuzz_replay_main.c tests/fuzz/fuzz_make_%.c,\
	$(wildcard tests/fuzz/fuzz_*.c))
FUZZ_ALL := $(sort $(patsubst tests/fuzz/fuzz_%.c,%,$(FUZZ_HARNESS_SRC)))
FUZZ_NAMES ?= $(FUZZ_ALL)
fuzz_comma := ,
override FUZZ_NAMES := $(filter $(FUZZ_ALL),$(subst $(fuzz_comma), ,$(FUZZ_NAMES)))

FUZZ_CC ?= clang
FUZZ_DIR ?= $(BUILD)/fuzz
FUZZ_SECONDS ?= 60
FUZZ_RUNS ?= 10000000
FUZZ_MAX_SECONDS ?= 7200
FUZZ_JOBS ?= 1
# a unit slower than this (seconds) is a finding (libFuzzer's -timeout)
FUZZ_TIMEOUT ?= 5
# one allocation above this many MB is a finding
FUZZ_MALLOC_LIMIT_MB ?= 512
FUZZ_SAN := -fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer
FUZZ_CFLAGS := -fsanitize=fuzzer-no-link $(FUZZ_SAN)
FUZZ_LDFLAGS := -fsanitize=fuzzer $(FUZZ_SAN)
# Inputs up to this many bytes (the seeds fit; larger inputs only slow the search down).
FUZZ_MAX_LEN_pack := 65536
FUZZ_MAX_LEN_mesh := 32768
FUZZ_MAX_LEN_fisheye := 16384
FUZZ_MAX_LEN_patch := 131072
FUZZ_MAX_LEN_proxy := 65536
FUZZ_MAX_LEN_shadow := 32768
FUZZ_MAX_LEN_hid := 4200
FUZZ_MAX_LEN_usb_desc := 1024
FUZZ_MAX_LEN_board := 8192
FUZZ_MAX_LEN_tour := 8192
FUZZ_MAX_LEN_hotspot := 256
FUZZ_MAX_LEN_object_line := 2048
FUZZ_MAX_LEN_obj := 16384
FUZZ_MAX_LEN_am_model := 262144
FUZZ_MAX_LEN_am_action := 65536
FUZZ_MAX_LEN_bpt := 16384
FUZZ_MAX_LEN_bvh := 16384
FUZZ_MAX_LEN_png := 16384
FUZZ_MAX_LEN_jpeg := 16384
FUZZ_MAX_LEN_tile_jpeg := 65536
FUZZ_MAX_LEN_image_rows := 16384
FUZZ_MAX_LEN_mjpeg := 16384
FUZZ_MAX_LEN_xmp := 16384
FUZZ_MAX_LEN_gltf := 16384
fuzz_targets = $(foreach n,$(1),$(n):$(or $(FUZZ_MAX_LEN_$(n)),4096))

# What a harness links: the layers' libraries of this build (the linker takes what the harness uses).
FUZZ_LINK_LIBS = $(FW_LIB) $(HAL_LIB) $(HOST_LIB) $(IO_LIB) $(CORE_LIB)
FUZZ_LINK_SYSLIBS = $(HAL_LIBS) $(IMG_LIBS) $(LDLIBS_HOST)

# ---- the libFuzzer build (run inside `make BUILD=$(FUZZ_DIR) CC=clang ...`) --------------------------
fuzz-harnesses: $(addprefix $(BUILD)/bin/fuzz_,$(FUZZ_NAMES))

$(BUILD)/bin/fuzz_%: $(BUILD)/obj/tests/fuzz/fuzz_%.o $(BUILD)/obj/tests/fuzz/fuzz_support.o $(FUZZ_LINK_LIBS)
	@mkdir -p $(@D)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(FUZZ_LINK_SYSLIBS)

fuzz-build:
	$(Q)$(MAKE) --no-print-directory CC=$(FUZZ_CC) BUILD=$(FUZZ_DIR) OPT="-O1 -g" CFLAGS="$(FUZZ_CFLAGS)" \
		LDFLAGS="$(FUZZ_LDFLAGS)" FUZZ_NAMES="$(FUZZ_NAMES)" fuzz-harnesses

FUZZ_RUN = sh scripts/fuzz-run --dir $(FUZZ_DIR) --timeout $(FUZZ_TIMEOUT) --malloc-limit-mb $(FUZZ_MALLOC_LIMIT_MB)

fuzz: fuzz-build
	$(Q)$(FUZZ_RUN) --seconds $(FUZZ_SECONDS) $(call fuzz_targets,$(FUZZ_NAMES))

fuzz-long: fuzz-build
	$(Q)$(FUZZ_RUN) --long --runs $(FUZZ_RUNS) --max-seconds $(FUZZ_MAX_SECONDS) --jobs $(FUZZ_JOBS) \
		$(call fuzz_targets,$(FUZZ_NAMES))

fuzz-merge: fuzz-build
	$(Q)$(FUZZ_RUN) --merge $(call fuzz_targets,$(FUZZ_NAMES))

# ---- corpus replay: a regression test of `make test` (and of `make check`'s sanitizer builds) --------------
FUZZ_REPLAY_DIR = $(BUILD)/fuzz-replay
FUZZ_REPLAY_BINS = $(addprefix $(FUZZ_REPLAY_DIR)/fuzz_,$(FUZZ_NAMES))

# compiled as the tests are (they may include every layer)
$(FUZZ_REPLAY_DIR)/obj/%.o: tests/fuzz/%.c
	@mkdir -p $(@D)
	@$(if $(Q),echo "  CC      $<")
	$(Q)$(CC) $(BASE_CFLAGS) $(HOSTED_DEFS) $(TEST_INC) $(IMG_CFLAGS) $(HAL_CFLAGS) $(CFLAGS) -c $< -o $@

$(FUZZ_REPLAY_DIR)/fuzz_%: $(FUZZ_REPLAY_DIR)/obj/fuzz_%.o $(FUZZ_REPLAY_DIR)/obj/fuzz_support.o \
		$(FUZZ_REPLAY_DIR)/obj/fuzz_replay_main.o $(FUZZ_LINK_LIBS)
	@mkdir -p $(@D)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(FUZZ_LINK_SYSLIBS)

# A seed maker (tests/fuzz/fuzz_make_mesh.c: OBJ -> mesh pack with the host tools' writer), for the corpora.
$(FUZZ_REPLAY_DIR)/fuzz_make_%: $(FUZZ_REPLAY_DIR)/obj/fuzz_make_%.o $(FUZZ_LINK_LIBS)
	@mkdir -p $(@D)
	@$(if $(Q),echo "  LD      $@")
	$(Q)$(CC) $(LDFLAGS) -o $@ $^ $(FUZZ_LINK_SYSLIBS)

-include $(wildcard $(FUZZ_REPLAY_DIR)/obj/*.d)

# The sanitizer options matter only in sanitizer builds (check-sanitize's BUILD and flags).
.PHONY: fuzz-replay-build
fuzz-replay-build: $(FUZZ_REPLAY_BINS)

check-fuzz-corpus: $(FUZZ_REPLAY_BINS)
	@echo "  CHECK   fuzz corpora replayed: $(words $(FUZZ_NAMES)) harnesses"
	$(Q)export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0 UBSAN_OPTIONS=print_stacktrace=1 \
		LSAN_OPTIONS=suppressions=$(CURDIR)/tests/sanitize/lsan.supp; \
	failed=; for n in $(FUZZ_NAMES); do \
		regress=tests/fuzz/regress/$$n; [ -d $$regress ] || regress=; \
		if $(FUZZ_REPLAY_DIR)/fuzz_$$n --name $$n tests/fuzz/corpus/$$n $$regress >$(FUZZ_REPLAY_DIR)/$$n.log 2>&1; \
		then sed 's/^/  /' $(FUZZ_REPLAY_DIR)/$$n.log; \
		else cat $(FUZZ_REPLAY_DIR)/$$n.log; failed="$$failed $$n"; fi; \
	done; \
	[ -z "$$failed" ] || { echo "check-fuzz-corpus: failed:$$failed (logs: $(FUZZ_REPLAY_DIR)/NAME.log)"; exit 1; }

