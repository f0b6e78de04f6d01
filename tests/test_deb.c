/* SPDX-License-Identifier: MIT */
/*
 * test_deb.c - the Debian package (mk/deb.mk, scripts/build-deb, packaging/deb/).
 *
 * `make test` builds the package of the native board (x86-kiosk on amd64) from
 * this build's binaries into $PSC_BIN_DIR/../deb/. This test takes it apart
 * with dpkg-deb and checks:
 *  - the control fields: name, the VERSION file's version, the host's
 *    architecture, Depends on adduser and the shared libraries;
 *  - the programs: exactly those of the build's list, $PSC_BIN_DIR/../programs.txt
 *    (the Makefile's PROGRAMS), in /usr/bin, each running --help, with exactly
 *    their manual pages in man1, each packaging/man/NAME.1 as it is; the
 *    description names each of them;
 *  - the file list: the sample scene, the documentation (copyright in Debian's machine-readable format, changelog,
 *    the panorama's attribution byte for byte), the unit, the board config,
 *    everything owned by root;
 *  - conffiles names the board config, whose scene lines name the packaged
 *    sample; the systemd unit's notify/watchdog/restart settings and user;
 *  - the unit's sandbox: `systemd-analyze security --offline=true` rates it
 *    2.5 or less (and the same check rates the unhardened unit of before
 *    above 2.5, so it can fail); its DeviceAllow= lines are exactly those of
 *    the devices the board names (scripts/build-deb --print unit, also for
 *    rpi-arm64, with no camera, and a framebuffer board with a watchdog);
 *  - the udev rules: installed, naming the periscope group, only for the
 *    board's devices; postinst reloads them only where udev runs;
 *    the maintainer scripts parse and guard starting the unit;
 *  - the packaged periscope-render renders the packaged scene;
 *  - the board file's manual page, periscope-board(5), is packaged as
 *    packaging/man/periscope-board.5 is (gzip -n: no name, no time), and
 *    (without a package too) scripts/check-man-board passes with its examples
 *    run on the sim board by this build's periscope: every board key, backend
 *    option and build key has an entry, groff -ww says nothing;
 *  - `dpkg --root` installs it into a scratch root (scripts run chrootless,
 *    DPKG_ROOT set: they must not touch this machine), registers the
 *    conffile, and purges it again.
 * Skipped with a message where dpkg-deb is missing or no package was built.
 */
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <setjmp.h>
#include <cmocka.h>

#include <ctype.h>
#include <glob.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#define SCENE "/usr/share/periscope/scenes/sample.pano"
#define OUT_MAX 65536

static char deb[1024];         /* the package, "" when skipping */
static char root[1024];        /* dpkg-deb -x / -e of it */
static char board[64];         /* the board it was built for (from its conffile) */
static const char *skip_reason;

/* Run a shell command; its standard output into out (if given). Returns the exit status. */
static int run(char *out, size_t outlen, const char *fmt, ...)
{
    char cmd[4096];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(cmd, sizeof cmd, fmt, ap);
    va_end(ap);
    FILE *p = popen(cmd, "r");
    if (!p)
        return -1;
    size_t n = 0;
    char sink[4096];
    for (;;) {
        char *dst = out ? out + n : sink;
        size_t room = out ? outlen - 1 - n : sizeof sink;
        if (room == 0)
            break;
        size_t got = fread(dst, 1, room, p);
        if (got == 0)
            break;
        if (out)
            n += got;
    }
    if (out)
        out[n] = '\0';
    int st = pclose(p);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static char *read_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    char *buf = malloc(OUT_MAX);
    size_t n = buf ? fread(buf, 1, OUT_MAX - 1, f) : 0;
    fclose(f);
    if (buf)
        buf[n] = '\0';
    return buf;
}

static char *root_file(const char *rel)
{
    char path[2048];
    snprintf(path, sizeof path, "%s%s", root, rel);
    return read_file(path);
}

/* One line of text (a whole line, exactly). */
static int has_line(const char *text, const char *line)
{
    size_t n = strlen(line);
    for (const char *p = text; p && *p; p = strchr(p, '\n') ? strchr(p, '\n') + 1 : NULL) {
        if (strncmp(p, line, n) == 0 && (p[n] == '\n' || p[n] == '\0'))
            return 1;
    }
    return 0;
}

/* A template placeholder (@NAME@, upper case) left in generated text. */
static int has_placeholder(const char *text)
{
    for (const char *p = strchr(text, '@'); p; p = strchr(p + 1, '@')) {
        size_t n = strspn(p + 1, "ABCDEFGHIJKLMNOPQRSTUVWXYZ_");
        if (n > 0 && p[1 + n] == '@')
            return 1;
    }
    return 0;
}

static int setup(void **state)
{
    (void)state;
    if (run(NULL, 0, "command -v dpkg-deb >/dev/null 2>&1") != 0) {
        skip_reason = "no dpkg-deb on this machine (dpkg)";
        return 0;
    }
    const char *bin = getenv("PSC_BIN_DIR");
    char dir[1024], pattern[1100];
    snprintf(dir, sizeof dir, "%s/../deb", bin && *bin ? bin : "build/bin");
    struct stat st;
    if (stat(dir, &st) != 0) {
        skip_reason = "no package was built (make test builds it; mk/deb.mk said why not)";
        return 0;
    }
    snprintf(pattern, sizeof pattern, "%s/periscope_*_*.deb", dir);
    glob_t g;
    if (glob(pattern, 0, NULL, &g) != 0 || g.gl_pathc != 1) {
        fprintf(stderr, "test_deb: want exactly one %s\n", pattern);
        return -1;
    }
    snprintf(deb, sizeof deb, "%s", g.gl_pathv[0]);
    globfree(&g);

    /* absolute: dpkg --root runs the maintainer scripts from another directory */
    const char *tmp = getenv("PSC_TEST_TMPDIR");
    char *abs = realpath(tmp && *tmp ? tmp : "/tmp", NULL);
    if (!abs) {
        fprintf(stderr, "test_deb: no scratch directory %s\n", tmp);
        return -1;
    }
    snprintf(root, sizeof root, "%s/deb-root", abs);
    free(abs);
    if (run(NULL, 0, "rm -rf '%s' && mkdir -p '%s' && dpkg-deb -x '%s' '%s' && dpkg-deb -e '%s' '%s/DEBIAN'", root,
            root, deb, root, deb, root) != 0) {
        fprintf(stderr, "test_deb: cannot unpack %s\n", deb);
        return -1;
    }
    char *conffiles = root_file("/DEBIAN/conffiles");
    if (!conffiles || sscanf(conffiles, "/etc/periscope/boards/%63[^/]/board.conf", board) != 1) {
        fprintf(stderr, "test_deb: %s: conffiles names no /etc/periscope/boards/BOARD/board.conf\n", deb);
        free(conffiles);
        return -1;
    }
    free(conffiles);
    printf("test_deb: %s (board %s)\n", deb, board);
    return 0;
}

#define SKIP_IF_NO_PACKAGE()                                                                                  \
    do {                                                                                                      \
        if (skip_reason) {                                                                                    \
            printf("test_deb: skipped: %s\n", skip_reason);                                                 \
            skip();                                                                                           \
        }                                                                                                     \
    } while (0)

/* ---- the programs: the build's list ------------------------------------------------ */

#define MAX_PROGRAMS 64
static char program_text[4096];
static const char *programs[MAX_PROGRAMS];
static size_t n_programs;

/* $PSC_BIN_DIR/../programs.txt (make all writes it, one name a line) into programs[]. */
static void read_program_list(void)
{
    const char *bin = getenv("PSC_BIN_DIR");
    char path[1100];
    snprintf(path, sizeof path, "%s/../programs.txt", bin && *bin ? bin : "build/bin");
    char *text = read_file(path);
    if (!text)
        fail_msg("no program list %s: make all writes it", path);
    snprintf(program_text, sizeof program_text, "%s", text);
    free(text);
    n_programs = 0;
    for (char *line = strtok(program_text, "\n"); line; line = strtok(NULL, "\n")) {
        if (line[0] < 'a' || line[0] > 'z' || strspn(line, "abcdefghijklmnopqrstuvwxyz0123456789-") != strlen(line))
            fail_msg("%s: '%s' is not a program name", path, line);
        if (n_programs == MAX_PROGRAMS)
            fail_msg("%s: more than %d programs", path, MAX_PROGRAMS);
        programs[n_programs++] = line;
    }
    int device = 0;
    for (size_t i = 0; i < n_programs; i++)
        device |= strcmp(programs[i], "periscope") == 0;
    if (!device)
        fail_msg("%s does not list the device program periscope", path);
}

static int is_listed(const char *name, size_t len)
{
    for (size_t i = 0; i < n_programs; i++) {
        if (strlen(programs[i]) == len && strncmp(programs[i], name, len) == 0)
            return 1;
    }
    return 0;
}

/* A whole word of text: not inside a longer name (letters, digits, '-', '_', '/', '.' around it). */
static int has_word(const char *text, const char *word)
{
    size_t n = strlen(word);
    for (const char *p = strstr(text, word); p; p = strstr(p + 1, word)) {
        int before = p == text || !(isalnum((unsigned char)p[-1]) || strchr("-_/.", p[-1]));
        int after = !(isalnum((unsigned char)p[n]) || (p[n] && strchr("-_/", p[n])));
        if (before && after)
            return 1;
    }
    return 0;
}

static void field(const char *name, char *out, size_t n)
{
    assert_int_equal(run(out, n, "dpkg-deb -f '%s' %s", deb, name), 0);
    out[strcspn(out, "\n")] = '\0';
}

static void test_control_fields(void **state)
{
    (void)state;
    SKIP_IF_NO_PACKAGE();
    char v[4096], want[256], arch[64];
    field("Package", v, sizeof v);
    assert_string_equal(v, "periscope");

    char *version = read_file("VERSION");
    assert_non_null(version);
    version[strcspn(version, " \n")] = '\0';
    field("Version", v, sizeof v);
    assert_string_equal(v, version);
    snprintf(want, sizeof want, "periscope_%s_", version);
    assert_non_null(strstr(deb, want));
    free(version);

    assert_int_equal(run(arch, sizeof arch, "dpkg --print-architecture"), 0);
    arch[strcspn(arch, "\n")] = '\0';
    field("Architecture", v, sizeof v);
    assert_string_equal(v, arch);

    field("Depends", v, sizeof v);
    assert_true(strncmp(v, "adduser, ", 9) == 0);
    assert_non_null(strstr(v, "libc6 (>= "));
    assert_non_null(strstr(v, "libdrm2"));
    assert_non_null(strstr(v, "libpng16-16"));
    field("Maintainer", v, sizeof v);
    assert_non_null(strchr(v, '@'));
    field("Installed-Size", v, sizeof v);
    assert_true(atol(v) > 1000);
    field("Description", v, sizeof v);
    assert_true(strlen(v) > 10);

    /* the description names every program of the build's list, its lines wrapped as Debian's policy asks */
    char desc[4096];
    assert_int_equal(run(desc, sizeof desc, "dpkg-deb -f '%s' Description", deb), 0);
    read_program_list();
    for (size_t i = 0; i < n_programs; i++) {
        if (!has_word(desc, programs[i]))
            fail_msg("the package's description does not name %s:\n%s", programs[i], desc);
    }
    for (const char *l = desc; *l; l += strcspn(l, "\n") + (l[strcspn(l, "\n")] != '\0')) {
        if (strcspn(l, "\n") > 80)
            fail_msg("a description line is longer than 80 characters: %.*s", (int)strcspn(l, "\n"), l);
    }
    assert_null(strchr(desc, '@')); /* no placeholder left */
}

static void test_file_list(void **state)
{
    (void)state;
    SKIP_IF_NO_PACKAGE();
    static char list[OUT_MAX];
    assert_int_equal(run(list, sizeof list, "dpkg-deb -c '%s'", deb), 0);
    char conf[256];
    snprintf(conf, sizeof conf, "./etc/periscope/boards/%s/board.conf", board);
    const char *want[] = {"." SCENE,
                          "./usr/share/doc/periscope/copyright",
                          "./usr/share/doc/periscope/changelog.gz",
                          "./usr/share/doc/periscope/ATTRIBUTION.md",
                          "./lib/systemd/system/periscope.service",
                          "./lib/udev/rules.d/60-periscope.rules",
                          "./usr/lib/modules-load.d/periscope.conf",
                          "./usr/share/man/man5/periscope-board.5.gz",
                          conf};
    for (size_t i = 0; i < sizeof want / sizeof want[0]; i++) {
        char line[300];
        snprintf(line, sizeof line, " %s\n", want[i]);
        if (!strstr(list, line))
            fail_msg("%s is not in the package", want[i]);
    }
    /* every entry root-owned, nothing in /usr/local, no stray build paths */
    for (char *l = list; *l; l = strchr(l, '\n') + 1) {
        assert_non_null(strstr(l, " root/root "));
        assert_null(strstr(l, "./usr/local"));
        if (!strchr(l, '\n'))
            break;
    }
}

/* The programs: exactly those of the build's list, each with its manual page as packaging/man/ has it, and each runs. */
static void test_programs(void **state)
{
    (void)state;
    SKIP_IF_NO_PACKAGE();
    static char list[OUT_MAX];
    assert_int_equal(run(list, sizeof list, "dpkg-deb -c '%s'", deb), 0);
    read_program_list();
    for (size_t i = 0; i < n_programs; i++) {
        char line[300];
        snprintf(line, sizeof line, " ./usr/bin/%s\n", programs[i]);
        if (!strstr(list, line))
            fail_msg("%s (listed in programs.txt) is not in the package's /usr/bin", programs[i]);
        snprintf(line, sizeof line, " ./usr/share/man/man1/%s.1.gz\n", programs[i]);
        if (!strstr(list, line))
            fail_msg("%s has no manual page in the package (/usr/share/man/man1/%s.1.gz)", programs[i], programs[i]);
        if (run(NULL, 0, "gzip -dc '%s/usr/share/man/man1/%s.1.gz' | cmp -s - 'packaging/man/%s.1'", root, programs[i],
                programs[i]) != 0)
            fail_msg("the packaged page of %s is not packaging/man/%s.1 (the package is older than the page?)",
                     programs[i], programs[i]);
        /* the programs are this machine's and run */
        if (run(NULL, 0, "'%s/usr/bin/%s' --help >/dev/null 2>&1", root, programs[i]) != 0)
            fail_msg("the packaged %s --help failed", programs[i]);
    }
    /* and nothing else: every file in /usr/bin and man1 is a listed program's */
    size_t bins = 0, pages = 0;
    for (const char *l = list; *l; l += strcspn(l, "\n") + (l[strcspn(l, "\n")] != '\0')) {
        const char *path = strstr(l, " ./");
        size_t len = strcspn(l, "\n");
        if (!path || path > l + len || l[0] == 'd')
            continue;
        path++;
        size_t plen = (size_t)(l + len - path);
        if (strncmp(path, "./usr/bin/", 10) == 0) {
            if (!is_listed(path + 10, plen - 10))
                fail_msg("the package has %.*s, which programs.txt does not list", (int)plen, path);
            bins++;
        } else if (strncmp(path, "./usr/share/man/man1/", 21) == 0) {
            if (plen < 21 + 5 || strncmp(path + plen - 5, ".1.gz", 5) != 0 || !is_listed(path + 21, plen - 21 - 5))
                fail_msg("the package has %.*s, the page of no program programs.txt lists", (int)plen, path);
            pages++;
        }
    }
    assert_int_equal(bins, n_programs);
    assert_int_equal(pages, n_programs);
    printf("test_deb: the package holds the %zu programs of programs.txt and their manual pages\n", n_programs);
}

static void test_conffile_and_board(void **state)
{
    (void)state;
    SKIP_IF_NO_PACKAGE();
    char want[256], rel[256];
    snprintf(want, sizeof want, "/etc/periscope/boards/%s/board.conf\n", board);
    char *conffiles = root_file("/DEBIAN/conffiles");
    assert_non_null(conffiles);
    assert_string_equal(conffiles, want); /* exactly the board config */
    free(conffiles);

    snprintf(rel, sizeof rel, "/etc/periscope/boards/%s/board.conf", board);
    char *conf = root_file(rel);
    assert_non_null(conf);
    assert_true(has_line(conf, "scene = " SCENE));
    /* every scene or camera_scene line names the packaged sample */
    for (const char *p = conf; (p = strstr(p, "scene =")) != NULL; p++) {
        const char *line = p;
        while (line > conf && line[-1] != '\n')
            line--;
        if (*line == '#')
            continue;   /* a commented example (x86-kiosk's camera) */
        assert_true(strncmp(p, "scene = " SCENE "\n", strlen("scene = " SCENE "\n")) == 0);
    }
    assert_true(has_line(conf, "watchdog = systemd"));
    free(conf);
}

static void test_unit(void **state)
{
    (void)state;
    SKIP_IF_NO_PACKAGE();
    char *unit = root_file("/lib/systemd/system/periscope.service");
    assert_non_null(unit);
    char exec[256];
    snprintf(exec, sizeof exec, "ExecStart=/usr/bin/periscope --board %s --boards-dir /etc/periscope/boards --quiet",
             board);
    const char *lines[] = {"[Unit]", "[Service]", "[Install]", "Type=notify", "NotifyAccess=main",
                           "Restart=on-failure", "RestartSec=2", "StartLimitIntervalSec=120",
                           "StartLimitBurst=5", "User=periscope", "Group=periscope",
                           "WantedBy=multi-user.target", exec};
    for (size_t i = 0; i < sizeof lines / sizeof lines[0]; i++) {
        if (!has_line(unit, lines[i]))
            fail_msg("the unit has no line '%s'", lines[i]);
    }
    /* the start limit belongs to [Unit], the restart policy to [Service] */
    assert_true(strstr(unit, "StartLimitBurst=") < strstr(unit, "[Service]"));
    const char *wd = strstr(unit, "\nWatchdogSec=");
    assert_non_null(wd);
    assert_true(atoi(wd + strlen("\nWatchdogSec=")) >= 1);
    assert_false(has_placeholder(unit)); /* no template placeholder left */
    free(unit);
}

/* ---- the unit's sandbox ---------------------------------------------------------- */

#define EXPOSURE_MAX 2.5

/* The unhardened unit of before (issue 16: 8.6 EXPOSED), for the check's self-test. */
static const char old_unit[] = "[Unit]\nDescription=Periscope\nAfter=systemd-udev-settle.service\n\n"
                               "[Service]\nType=notify\nNotifyAccess=main\n"
                               "ExecStart=/usr/bin/periscope --board x86-kiosk --boards-dir /etc/periscope/boards --quiet\n"
                               "User=periscope\nGroup=periscope\nWorkingDirectory=/var/lib/periscope\n"
                               "WatchdogSec=2\nRestart=on-failure\nNoNewPrivileges=yes\nProtectSystem=full\n"
                               "ProtectHome=read-only\nPrivateTmp=yes\n\n[Install]\nWantedBy=multi-user.target\n";

/* systemd-analyze's overall exposure of a unit file (its name must end in .service):
 * 0 with *level set, 1 when systemd-analyze is not there, -1 on another failure. */
static int exposure(const char *unit, double *level)
{
    static char out[OUT_MAX];
    if (run(NULL, 0, "command -v systemd-analyze >/dev/null 2>&1") != 0)
        return 1;
    int rc = run(out, sizeof out, "systemd-analyze security --offline=true '%s' 2>&1", unit);
    const char *p = strstr(out, "Overall exposure level for ");
    p = p ? strstr(p, ": ") : NULL;
    if (rc != 0 || !p || sscanf(p + 2, "%lf", level) != 1) {
        fprintf(stderr, "test_deb: systemd-analyze security --offline=true %s (status %d):\n%s\n", unit, rc, out);
        return -1;
    }
    const char *eol = strchr(p, '\n');
    printf("test_deb: %s: exposure %.*s\n", unit, eol ? (int)(eol - p - 2) : 20, p + 2);
    return 0;
}

#define SKIP_IF_NO_ANALYZE(rc)                                                                                \
    do {                                                                                                      \
        if ((rc) == 1) {                                                                                      \
            printf("test_deb: skipped: no systemd-analyze (Debian: systemd, in scripts/install-deps.sh)\n"); \
            skip();                                                                                           \
        }                                                                                                     \
    } while (0)

static void test_unit_exposure(void **state)
{
    (void)state;
    SKIP_IF_NO_PACKAGE();
    char unit[1100];
    double level = 99;
    snprintf(unit, sizeof unit, "%s/lib/systemd/system/periscope.service", root);
    int rc = exposure(unit, &level);
    SKIP_IF_NO_ANALYZE(rc);
    assert_int_equal(rc, 0);
    if (level > EXPOSURE_MAX)
        fail_msg("the unit's exposure is %.1f, more than %.1f", level, EXPOSURE_MAX);
}

/* The same check on the unit before the hardening must fail (8.6). */
static void test_unit_exposure_rejects_unhardened_unit(void **state)
{
    (void)state;
    char dir[1100], unit[1200];
    double level = 0;
    snprintf(dir, sizeof dir, "%s/old-unit", getenv("PSC_TEST_TMPDIR") && *getenv("PSC_TEST_TMPDIR")
                                                   ? getenv("PSC_TEST_TMPDIR")
                                                   : "/tmp");
    snprintf(unit, sizeof unit, "%s/periscope.service", dir);
    assert_int_equal(run(NULL, 0, "mkdir -p '%s'", dir), 0);
    FILE *f = fopen(unit, "w");
    assert_non_null(f);
    fputs(old_unit, f);
    fclose(f);
    int rc = exposure(unit, &level);
    SKIP_IF_NO_ANALYZE(rc);
    assert_int_equal(rc, 0);
    if (level <= EXPOSURE_MAX)
        fail_msg("the unhardened unit rates %.1f: the exposure check cannot fail", level);
}

/* The unit's DeviceAllow= values, "|"-joined in file order. */
static void device_allow(const char *unit, char *out, size_t n)
{
    out[0] = '\0';
    for (const char *p = unit; p && *p; p = strchr(p, '\n') ? strchr(p, '\n') + 1 : NULL) {
        if (strncmp(p, "DeviceAllow=", 12) == 0) {
            size_t len = strcspn(p + 12, "\n"), used = strlen(out);
            snprintf(out + used, n - used, "%s%.*s", used ? "|" : "", (int)len, p + 12);
        }
    }
}

/* scripts/build-deb --print WHAT for a board (or a board file) into a buffer. */
static char *print_for(const char *board_name, const char *conf, const char *what)
{
    static char out[OUT_MAX];
    int rc = run(out, sizeof out, "sh scripts/build-deb --board '%s' %s%s%s --print %s 2>&1", board_name,
                 conf ? "--conf '" : "", conf ? conf : "", conf ? "'" : "", what);
    if (rc != 0)
        fail_msg("scripts/build-deb --board %s --print %s failed (%d):\n%s", board_name, what, rc, out);
    return out;
}

static void test_unit_device_allow(void **state)
{
    (void)state;
    char got[1024];

    /* the packaged unit: the board's display, gamepad and camera classes */
    if (!skip_reason) {
        char *unit = root_file("/lib/systemd/system/periscope.service");
        assert_non_null(unit);
        assert_true(has_line(unit, "DevicePolicy=closed"));
        assert_true(has_line(unit, "CapabilityBoundingSet="));
        assert_true(has_line(unit, "PrivateNetwork=yes"));
        assert_true(has_line(unit, "StateDirectory=periscope"));
        assert_null(strstr(unit, "systemd-udev-settle")); /* deprecated */
        device_allow(unit, got, sizeof got);
        printf("test_deb: the %s unit allows %s\n", board, got);
        if (strcmp(board, "x86-kiosk") == 0) {
            /* no camera unless the board names one (x86-kiosk's is commented out) */
            assert_string_equal(got, "char-drm rw|char-usb_device rw|char-input r");
            assert_true(has_line(unit, "RestrictAddressFamilies=AF_UNIX AF_NETLINK"));
        }
        free(unit);
    }
    /* rpi-arm64: DRM, GPIO buttons, a gamepad and the kernel's input devices (evdev: read only), no camera */
    device_allow(print_for("rpi-arm64", NULL, "unit"), got, sizeof got);
    assert_string_equal(got, "char-drm rw|char-gpiochip rw|char-usb_device rw|char-input r");
    assert_true(has_line(print_for("rpi-arm64", NULL, "modules"), "evdev"));
    assert_non_null(strstr(print_for("rpi-arm64", NULL, "udev-rules"),
                           "SUBSYSTEM==\"input\", KERNEL==\"event[0-9]*\", ENV{ID_INPUT_TOUCHSCREEN}==\"1\", "
                           "GROUP=\"periscope\", MODE=\"0660\""));

    /* a framebuffer board with its console, the kernel's watchdog, no gamepad:
     * exactly those nodes, the console as the controlling terminal, no netlink */
    char dir[1100], conf[1200];
    snprintf(dir, sizeof dir, "%s/fb-board", getenv("PSC_TEST_TMPDIR") && *getenv("PSC_TEST_TMPDIR")
                                                 ? getenv("PSC_TEST_TMPDIR")
                                                 : "/tmp");
    snprintf(conf, sizeof conf, "%s/board.conf", dir);
    assert_int_equal(run(NULL, 0, "mkdir -p '%s'", dir), 0);
    FILE *f = fopen(conf, "w");
    assert_non_null(f);
    fputs("debian_arch = amd64\ndisplay = fbdev\ndisplay_size = 640x480\ndisplay.device = /dev/fb1\n"
          "display.console = /dev/tty1\ninput = gpio\ninput.line.home = GPIO17\nclock = linux\n"
          "watchdog = linux\nwatchdog_timeout_ms = 4000\ncamera = none\nscene = a.pano\n",
          f);
    fclose(f);
    char *unit = print_for("fb-board", conf, "unit");
    device_allow(unit, got, sizeof got);
    assert_string_equal(got, "/dev/fb1 rw|/dev/tty1 rw|char-gpiochip rw|/dev/watchdog0 rw");
    assert_true(has_line(unit, "TTYPath=/dev/tty1"));
    assert_true(has_line(unit, "RestrictAddressFamilies=AF_UNIX"));
    assert_true(has_line(unit, "WatchdogSec=4"));
    assert_false(has_placeholder(unit));
    assert_null(strstr(unit, "char-input"));   /* no evdev in its input */
    char *rules = print_for("fb-board", conf, "udev-rules");
    assert_non_null(strstr(rules, "KERNEL==\"gpiochip[0-9]*\", GROUP=\"periscope\""));
    assert_non_null(strstr(rules, "KERNEL==\"watchdog0\", GROUP=\"periscope\""));
    assert_null(strstr(rules, "SUBSYSTEM==\"usb\""));
    assert_null(strstr(rules, "SUBSYSTEM==\"input\""));

    /* the same board with a UVC camera named: video4linux and its module, nothing else more */
    f = fopen(conf, "a");
    assert_non_null(f);
    fputs("camera = v4l2\ncamera.device = /dev/video0\ncamera_scene = a.pano\n", f);
    fclose(f);
    assert_int_equal(run(NULL, 0, "sed -i '/^camera = none$/d' '%s'", conf), 0);
    device_allow(print_for("fb-board", conf, "unit"), got, sizeof got);
    assert_string_equal(got, "/dev/fb1 rw|/dev/tty1 rw|char-gpiochip rw|char-video4linux rw|/dev/watchdog0 rw");
    assert_true(has_line(print_for("fb-board", conf, "modules"), "videodev"));
}

static void test_udev_rules(void **state)
{
    (void)state;
    SKIP_IF_NO_PACKAGE();
    char *rules = root_file("/lib/udev/rules.d/60-periscope.rules");
    if (!rules)
        fail_msg("the package has no /lib/udev/rules.d/60-periscope.rules");
    assert_non_null(strstr(rules, "GROUP=\"periscope\""));
    if (strcmp(board, "x86-kiosk") == 0) {
        /* a gamepad, no GPIO buttons, no hardware watchdog */
        assert_non_null(strstr(rules, "SUBSYSTEM==\"usb\", ENV{DEVTYPE}==\"usb_device\", "
                                      "ENV{ID_USB_INTERFACES}==\"*:0300??:*\", GROUP=\"periscope\", MODE=\"0660\""));
        assert_null(strstr(rules, "gpiochip"));
        assert_null(strstr(rules, "KERNEL==\"watchdog"));
    }
    free(rules);
    char *modules = root_file("/usr/lib/modules-load.d/periscope.conf");
    assert_non_null(modules);
    if (strcmp(board, "x86-kiosk") == 0)
        assert_true(has_line(modules, "drm") && has_line(modules, "usbcore") && has_line(modules, "evdev") &&
                    !has_line(modules, "videodev"));
    free(modules);
    /* postinst applies them where udev runs, never in a chroot or image build */
    char *postinst = root_file("/DEBIAN/postinst");
    assert_non_null(postinst);
    const char *reload = strstr(postinst, "udevadm control --reload-rules");
    assert_non_null(reload);
    const char *guard = strstr(postinst, "[ -d /run/udev ]");
    assert_true(guard && guard < reload);
    free(postinst);
}

static void test_docs_and_scripts(void **state)
{
    (void)state;
    SKIP_IF_NO_PACKAGE();
    char *copyright = root_file("/usr/share/doc/periscope/copyright");
    assert_non_null(copyright);
    assert_true(strncmp(copyright, "Format: https://www.debian.org/doc/packaging-manuals/copyright-format/1.0/\n",
                        75) == 0);
    assert_true(has_line(copyright, "Files: *"));
    assert_true(has_line(copyright, "License: Expat"));   /* the source tree's LICENSE: MIT */
    assert_null(strstr(copyright, "all rights reserved"));
    assert_true(has_line(copyright, "Files: usr/share/periscope/scenes/*"));
    assert_true(has_line(copyright, "License: CC-BY-SA-3.0"));
    free(copyright);

    char *ours = root_file("/usr/share/doc/periscope/ATTRIBUTION.md");
    char *src = read_file("assets/ATTRIBUTION.md");
    assert_non_null(ours);
    assert_non_null(src);
    assert_string_equal(ours, src);
    free(ours);
    free(src);

    char top[512], version[64];
    assert_int_equal(run(top, sizeof top, "gzip -dc '%s/usr/share/doc/periscope/changelog.gz' | head -n 1", root), 0);
    assert_int_equal(run(version, sizeof version, "dpkg-deb -f '%s' Version", deb), 0);
    version[strcspn(version, "\n")] = '\0';
    char want[128];
    snprintf(want, sizeof want, "periscope (%s) ", version);
    assert_true(strncmp(top, want, strlen(want)) == 0);

    const char *scripts[] = {"postinst", "prerm", "postrm"};
    for (size_t i = 0; i < 3; i++) {
        if (run(NULL, 0, "sh -n '%s/DEBIAN/%s'", root, scripts[i]) != 0)
            fail_msg("DEBIAN/%s does not parse", scripts[i]);
    }
    char *postinst = root_file("/DEBIAN/postinst");
    assert_non_null(postinst);
    assert_non_null(strstr(postinst, "adduser --quiet --system --group --home /var/lib/periscope periscope"));
    assert_non_null(strstr(postinst, "deb-systemd-helper enable"));
    /* starts only on a running systemd: not in a chroot or image build */
    assert_non_null(strstr(postinst, "[ -d /run/systemd/system ]"));
    assert_true(strstr(postinst, "[ -d /run/systemd/system ]") < strstr(postinst, "deb-systemd-invoke restart"));
    free(postinst);
}

static void test_scene_renders(void **state)
{
    (void)state;
    SKIP_IF_NO_PACKAGE();
    char png[1100];
    snprintf(png, sizeof png, "%s-view.png", root);
    unlink(png);
    assert_int_equal(run(NULL, 0, "'%s/usr/bin/periscope-render' '%s" SCENE "' -o '%s' --yaw 30 2>&1", root, root, png),
                     0);
    struct stat st;
    assert_int_equal(stat(png, &st), 0);
    assert_true(st.st_size > 1000);
}

/* The board file's manual page: in the package as in the source tree, compressed with gzip -n. */
static void test_board_manual_packaged(void **state)
{
    (void)state;
    SKIP_IF_NO_PACKAGE();
    char gz[1100], head[64];
    snprintf(gz, sizeof gz, "%s/usr/share/man/man5/periscope-board.5.gz", root);
    if (run(NULL, 0, "gzip -dc '%s' | cmp -s - packaging/man/periscope-board.5", gz) != 0)
        fail_msg("%s is not packaging/man/periscope-board.5 (the package is older than the page?)", gz);
    /* gzip header: flags (byte 3) without FNAME, modification time (bytes 4..7) zero */
    assert_int_equal(run(head, sizeof head, "od -An -tu1 -N8 '%s' | tr -s ' \\n' ' '", gz), 0);
    unsigned b[8];
    assert_int_equal(sscanf(head, "%u %u %u %u %u %u %u %u", &b[0], &b[1], &b[2], &b[3], &b[4], &b[5], &b[6], &b[7]), 8);
    assert_int_equal(b[0], 0x1f);
    assert_int_equal(b[1], 0x8b);
    assert_int_equal(b[3] & 0x08u, 0);
    assert_int_equal(b[4] | b[5] | b[6] | b[7], 0);
}

/*
 * The page documents every key the sources read and renders without warnings, and its examples run on the
 * sim board (scripts/check-man-board); no package needed.
 */
static void test_board_manual_complete(void **state)
{
    (void)state;
    if (run(NULL, 0, "command -v groff >/dev/null 2>&1") != 0) {
        printf("test_deb: skipped: no groff to render the manual page (sh scripts/install-deps.sh groff-base)\n");
        skip();
    }
    const char *bin = getenv("PSC_BIN_DIR"), *tmp = getenv("PSC_TEST_TMPDIR");
    char scene[64] = "", out[OUT_MAX];
    struct stat st;
    if (stat("out/sample.pano", &st) == 0)
        snprintf(scene, sizeof scene, "--scene out/sample.pano");   /* else the sample JPEG, packed at start-up */
    int rc = run(out, sizeof out, "TMPDIR='%s' sh scripts/check-man-board --periscope '%s/periscope' %s 2>&1",
                 tmp && *tmp ? tmp : "/tmp", bin && *bin ? bin : "build/bin", scene);
    printf("%s", out);
    if (rc != 0)
        fail_msg("scripts/check-man-board failed (%d)", rc);
}

static void test_dpkg_root_install(void **state)
{
    (void)state;
    SKIP_IF_NO_PACKAGE();
    char inst[1100], out[OUT_MAX];
    snprintf(inst, sizeof inst, "%s-installed", root);
    assert_int_equal(run(NULL, 0,
                         "rm -rf '%s' && mkdir -p '%s/var/lib/dpkg/info' '%s/var/lib/dpkg/updates' && "
                         ": > '%s/var/lib/dpkg/status'",
                         inst, inst, inst, inst),
                     0);
    /* chrootless: DPKG_ROOT is set, so the scripts leave this machine alone */
    int rc = run(out, sizeof out,
                 "dpkg --root='%s' --force-script-chrootless --force-depends --force-not-root --log=/dev/null "
                 "-i '%s' 2>&1",
                 inst, deb);
    if (rc != 0)
        fail_msg("dpkg --root -i failed (%d):\n%s", rc, out);
    assert_int_equal(run(out, sizeof out, "dpkg --root='%s' -s periscope", inst), 0);
    assert_true(has_line(out, "Status: install ok installed"));
    char conf[256];
    snprintf(conf, sizeof conf, " /etc/periscope/boards/%s/board.conf ", board);
    assert_non_null(strstr(out, conf));
    char path[2048];
    snprintf(path, sizeof path, "%s/usr/bin/periscope", inst);
    assert_int_equal(access(path, X_OK), 0);

    rc = run(out, sizeof out, "dpkg --root='%s' --force-script-chrootless --force-not-root --log=/dev/null -P periscope 2>&1",
             inst);
    if (rc != 0)
        fail_msg("dpkg --root -P failed (%d):\n%s", rc, out);
    snprintf(path, sizeof path, "%s/etc/periscope/boards/%s/board.conf", inst, board);
    assert_int_not_equal(access(path, F_OK), 0); /* purged, conffile too */
    run(NULL, 0, "rm -rf '%s'", inst);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_control_fields),    cmocka_unit_test(test_file_list),
        cmocka_unit_test(test_programs),
        cmocka_unit_test(test_conffile_and_board), cmocka_unit_test(test_unit),
        cmocka_unit_test(test_unit_exposure),     cmocka_unit_test(test_unit_exposure_rejects_unhardened_unit),
        cmocka_unit_test(test_unit_device_allow), cmocka_unit_test(test_udev_rules),
        cmocka_unit_test(test_docs_and_scripts),  cmocka_unit_test(test_scene_renders),
        cmocka_unit_test(test_board_manual_packaged), cmocka_unit_test(test_board_manual_complete),
        cmocka_unit_test(test_dpkg_root_install),
    };
    return cmocka_run_group_tests(tests, setup, NULL);
}
