#!/usr/bin/env bash
# Keeps the docs short to read, and their links whole.
#   1. README.md under 130 lines; every user doc (docs/**/*.md and tests/README.md, except the
#      results files: docs/results/**, docs/pricelist/**/report.md, *_report.md) under 250 lines;
#   2. in those, no prose line over 120 characters (lines inside ``` fences and table rows,
#      which start with `|`, are not prose);
#   3. every relative markdown link in README.md, tests/README.md and docs/ (results files
#      included) names a file that exists and, for a #fragment into a markdown file, one of
#      its headings (GitHub's anchors: lower case, punctuation dropped, spaces as hyphens).
# Prints each offender as path:line: what; exits 1 if there is any, else 0.
# Usage: scripts/check_docs.sh
set -euo pipefail
cd "$(dirname "$0")/.."
export LC_ALL=C

readme_limit=130  # lines, exclusive
doc_limit=250     # lines, exclusive
width=120         # characters of a prose line, inclusive

is_results_file() {
  case "$1" in
    docs/results/*) return 0 ;;
    docs/pricelist/*/report.md) return 0 ;;
    *_report.md) return 0 ;;
  esac
  return 1
}

all_docs=(README.md)
[ -f tests/README.md ] && all_docs+=(tests/README.md)
while IFS= read -r f; do all_docs+=("$f"); done < <(find docs -name '*.md' -type f | sort)

user_docs=()
for f in "${all_docs[@]}"; do
  is_results_file "$f" || user_docs+=("$f")
done

failures=0
fail() {
  echo "$1"
  failures=$((failures + 1))
}

# 1. Length.
for f in "${user_docs[@]}"; do
  limit=$doc_limit
  [ "$f" = README.md ] && limit=$readme_limit
  n=$(wc -l <"$f")
  if [ "$n" -ge "$limit" ]; then
    fail "$f:$n: $n lines; the limit is $((limit - 1))"
  fi
done

# 2. Width of prose lines, in characters (UTF-8 continuation bytes not counted).
for f in "${user_docs[@]}"; do
  while IFS= read -r line; do
    fail "$line"
  done < <(awk -v file="$f" -v width="$width" '
    /^[ \t]*(```|~~~)/ { fence = !fence; next }
    fence { next }
    /^[ \t]*\|/ { next }
    {
      s = $0
      gsub(/[\200-\277]/, "", s)
      if (length(s) > width) printf "%s:%d: %d characters; the limit is %d\n", file, NR, length(s), width
    }' "$f")
done

# 3. Links. Prints "line<TAB>target<TAB>fragment" for every inline link or image outside fences
# and code spans; the fragment lower-cased and without bytes outside ASCII, as anchors_of makes
# anchors.
links_of() {
  awk '
    /^[ \t]*(```|~~~)/ { fence = !fence; next }
    fence { next }
    {
      s = $0
      gsub(/``[^`]*``/, "", s)
      gsub(/`[^`]*`/, "", s)
      while (match(s, /\]\([^)]*\)/)) {
        t = substr(s, RSTART + 2, RLENGTH - 3)
        s = substr(s, RSTART + RLENGTH)
        sub(/^[ \t]*</, "", t); sub(/>[ \t]*$/, "", t)
        sub(/[ \t].*$/, "", t)  # a title after the target
        f = ""
        if (index(t, "#") > 0) {
          f = tolower(substr(t, index(t, "#") + 1))
          gsub(/[\200-\377]/, "", f)
        }
        if (t != "") printf "%d\t%s\t%s\n", NR, t, f
      }
    }' "$1"
}

# The anchors of a markdown file's headings, one a line, as GitHub makes them; bytes outside
# ASCII are dropped here and from the links' fragments alike.
anchors_of() {
  awk '
    /^[ \t]*(```|~~~)/ { fence = !fence; next }
    fence { next }
    /^#+[ \t]/ {
      h = $0
      sub(/^#+[ \t]+/, "", h); sub(/[ \t]+#*[ \t]*$/, "", h)
      while (match(h, /\[[^]]*\]\([^)]*\)/)) {  # [text](url) -> text
        inner = substr(h, RSTART + 1, RLENGTH - 2)
        sub(/\]\(.*$/, "", inner)
        h = substr(h, 1, RSTART - 1) inner substr(h, RSTART + RLENGTH)
      }
      h = tolower(h)
      gsub(/[^a-z0-9 _-]/, "", h)
      gsub(/ /, "-", h)
      if (h in seen) { seen[h]++; h = h "-" seen[h] } else seen[h] = 0
      print h
    }' "$1"
}

declare -A anchor_cache
has_anchor() {  # file anchor (normalised by links_of)
  local file=$1 anchor=$2
  if [ -z "${anchor_cache[$file]+x}" ]; then
    anchor_cache[$file]=$'\n'"$(anchors_of "$file")"$'\n'
  fi
  [[ ${anchor_cache[$file]} == *$'\n'"$anchor"$'\n'* ]]
}

for f in "${all_docs[@]}"; do
  dir=$(dirname "$f")
  while IFS=$'\t' read -r n target fragment; do
    case "$target" in
      [a-zA-Z]*:*) continue ;;  # http:, https:, mailto:
    esac
    path=${target%%#*}
    if [ -z "$path" ]; then
      resolved=$f
    else
      resolved=$dir/$path
    fi
    if [ ! -e "$resolved" ]; then
      fail "$f:$n: broken link $target (no $resolved)"
    elif [ -n "$fragment" ] && [[ $resolved == *.md ]] && [ -f "$resolved" ] &&
        ! has_anchor "$resolved" "$fragment"; then
      fail "$f:$n: broken link $target (no heading #$fragment in $resolved)"
    fi
  done < <(links_of "$f")
done

if [ "$failures" -gt 0 ]; then
  echo "check_docs: $failures problem(s)" >&2
  exit 1
fi
echo "check_docs: ${#user_docs[@]} docs within their limits, every link whole"
