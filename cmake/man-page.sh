#!/bin/sh
# Writes dentsim's man page (roff) from the built binary's own --help, every command's and subcommand's, so the page says what the program does.
#
# Usage: man-page.sh DENTSIM VERSION DATA_DIR OUT
#   DENTSIM   the built binary, run only with --help
#   VERSION   the project's version, for the page's header
#   DATA_DIR  where the package puts share/dentsim (/usr/share/dentsim), for FILES
#   OUT       the page to write (dentsim.1); cmake/Packaging.cmake gzips it
# Run by the dentsim_man target (cmake/Packaging.cmake). POSIX sh and awk, so mawk does.
set -eu

if [ $# -ne 4 ]; then
  echo "man-page.sh: usage: man-page.sh DENTSIM VERSION DATA_DIR OUT" >&2
  exit 2
fi
dentsim=$1 version=$2 data=$3 out=$4
if [ ! -x "$dentsim" ]; then
  echo "man-page.sh: $dentsim is not an executable" >&2
  exit 1
fi

# One help text as roff. CLI11 prints section heads ("Options:", "Subcommands:"), then entries: two
# spaces and the option or command, padded to column 30 with its description from column 31, or,
# when the name reaches column 30, the description on the next line; a description's own further
# lines are indented 30. Entries become tagged paragraphs, other lines text. An entry's line is
# held until the next line shows whether a description follows there.
# roff escapes: a backslash is \e, a line starting with . or ' gets \& in front, and a hyphen in an
# option is \- (a minus sign that man pages copy and paste correctly).
to_roff() {
  sed 's|^Usage: [^ ]*/dentsim|Usage: dentsim|' | awk '
    function esc(s) { gsub(/\\/, "\\e", s); return s }
    function lead(s) { if (s ~ /^[.'"'"']/) s = "\\&" s; return s }
    function opt(s) { s = esc(s); gsub(/-/, "\\-", s); return s }
    function trim(s) { sub(/^ +/, "", s); sub(/ +$/, "", s); return s }
    # raw: the entry line less its two leading spaces; column 30 is raw[28], column 31 raw[29].
    # padded: a description starts at column 31 after a space; certain when columns 29-30 are both
    # spaces (no name holds two), else a 27-character name and one space, or a long name with a
    # space at column 30: then a description on the next line says it was the long name.
    function resolve(next_is_more,   padded) {
      padded = length(raw) > 28 && substr(raw, 28, 1) == " " && substr(raw, 29, 1) != " "
      if (padded && (substr(raw, 27, 2) == "  " || !next_is_more)) {
        term = trim(substr(raw, 1, 27)); desc = trim(substr(raw, 29))
      } else {
        term = trim(raw); desc = ""
      }
      pending = 0
    }
    function flush() {
      if (pending) resolve(0)
      if (term != "") { print ".TP"; print "\\fB" opt(term) "\\fR"; if (desc != "") print lead(esc(desc)) }
      term = ""; desc = ""
    }
    /^[^ ].*:$/ && !/^Usage:/ { flush(); print ".PP"; print "\\fB" esc($0) "\\fR"; next }
    /^  [^ ]/ { flush(); raw = substr($0, 3); pending = 1; next }
    /^                              +[^ ]/ && (pending || term != "") {
      if (pending) resolve(1)
      d = trim($0); desc = (desc == "" ? d : desc " " d); next
    }
    /^ *$/ { flush(); next }
    { flush(); print ".PP"; print lead(esc(trim($0))) }
    END { flush() }
  '
}

# The commands a help text lists under "Subcommands:", one a line.
subcommands() {
  awk '/^[A-Z][A-Za-z ]*:$/ { inside = ($0 == "Subcommands:"); next }
       inside && /^  [^ ]/ { print $1 }'
}

# One line as is: dash's echo would read \f and \e as escapes.
line() { printf '%s\n' "$*"; }

# A command's section, then its subcommands' sections, depth first: "dentsim task", "dentsim task new".
command_sections() {
  path=$1
  # shellcheck disable=SC2086  # the path is the command's words, split on purpose
  help=$("$dentsim" $path --help) || { echo "man-page.sh: dentsim $path --help failed" >&2; exit 1; }
  printf '.SS "dentsim %s"\n' "$path"
  printf '%s\n' "$help" | to_roff
  for sub in $(printf '%s\n' "$help" | subcommands); do
    (command_sections "$path $sub")  # a subshell: the recursion keeps this call's $path
  done
}

top=$("$dentsim" --help) || { echo "man-page.sh: $dentsim --help failed" >&2; exit 1; }
# The first line reads "dentsim: what it is"; NAME takes what it is.
summary=$(printf '%s\n' "$top" | head -n 1 | sed 's/^dentsim: //')
tmp="$out.tmp"
{
  printf '.TH DENTSIM 1 "" "dentsim %s" "User Commands"\n' "$version"
  line ".SH NAME"
  printf 'dentsim \\- %s\n' "$(printf '%s' "$summary" | sed 's/\\/\\e/g')"
  line ".SH SYNOPSIS"
  line '\fBdentsim\fR [\fIOPTIONS\fR] \fICOMMAND\fR [\fICOMMAND OPTIONS\fR]'
  line ".SH DESCRIPTION"
  line "One program with a command for each job: the simulator (\\fBrun\\fR, \\fBdemo\\fR), replay, scoring,"
  line "tasks and courses, class reports, learning records, teeth from STL and CT scans, and benchmarks."
  line "Each command's section below is its \\fB\\-\\-help\\fR text. Errors are one line starting"
  line "\"dentsim:\", and the exit status is 0 on success, 1 on failure."
  line ".SH OPTIONS"
  printf '%s\n' "$top" | sed '1d' | to_roff
  line ".SH COMMANDS"
  for sub in $(printf '%s\n' "$top" | subcommands); do
    command_sections "$sub"
  done
  line ".SH ENVIRONMENT"
  line ".TP"
  line ".B DENTSIM_DEVICE"
  line "The Vulkan device, by index or name substring, when no \\fB\\-\\-device\\fR is given."
  line ".TP"
  line ".B DENTSIM_VALIDATION"
  line "1 turns on the Khronos validation layer."
  line ".TP"
  line ".B DENTSIM_CONFIG"
  line "The learning records' config file (default \\fI~/.config/dentsim/learning.json\\fR)."
  line ".SH FILES"
  line ".TP"
  printf '.I %s/tasks\n' "$data"
  line "The default course: \\fBrun\\fR lists its tasks when no \\fB\\-\\-course\\fR is given and the"
  line "current folder holds no \\fIassets/tasks\\fR. A course is a folder of task files to copy."
  line ".TP"
  printf '.I %s/teeth, tools, presets\n' "$data"
  line "The built-in molar's layers, its neighbours, the tools and the default preset, as the files"
  line "dentsim embeds; copies to start a task or a preset from."
  line ".TP"
  line ".I /usr/lib/udev/rules.d/70-dentsim.rules"
  line "Lets the user at the seat (and group plugdev) open the haptic pens, foot pedals and"
  line "/dev/cpu_dma_latency; replug a device after installing."
  line ".TP"
  line ".I ~/.local/share/dentsim/outbox.jsonl"
  line "Learning records waiting for the school's LRS."
  line ".SH SEE ALSO"
  line "\\fBdentsim \\fICOMMAND\\fB \\-\\-help\\fR; README.md and docs/ in dentsim's source."
} >"$tmp"
mv "$tmp" "$out"
