#!/usr/bin/env bash
# Lists every C++ function (and lambda) in the product longer than the limit, longest
# first, from universal-ctags' line:/end: fields. A function of N lines spans end-start+1.
# Exit: 0 none over the limit, 1 some, 2 ctags missing or not universal-ctags.
set -euo pipefail
cd "$(dirname "$0")/.."

limit=${FUNCTION_LENGTH_LIMIT:-80}
dirs=(layer foveation gaze_provider gpu tools samples)  # the product: not eval/ (the lab), tests/, bench/

if ! command -v ctags >/dev/null; then
  echo "check_function_length: ctags not found; install universal-ctags (apt-get install universal-ctags)" >&2
  exit 2
fi
if ! ctags --version 2>/dev/null | grep -q 'Universal Ctags'; then
  echo "check_function_length: $(command -v ctags) is not universal-ctags (needs its end: field); install universal-ctags" >&2
  exit 2
fi

present=()
for d in "${dirs[@]}"; do [[ -d $d ]] && present+=("$d"); done

out=$(ctags -R --languages=C++ --kinds-C++=f --fields=+ne --sort=no -o - "${present[@]}" |
  awk -F'\t' -v limit="$limit" '
    {
      start = 0; end = 0; scope = ""
      for (i = 3; i <= NF; i++) {
        if ($i ~ /^line:[0-9]+$/) start = substr($i, 6)
        else if ($i ~ /^end:[0-9]+$/) end = substr($i, 5)
        else if ($i ~ /^function:/) scope = substr($i, 10)
      }
      if (!start || !end) next
      checked++
      n = end - start + 1
      if (n <= limit) next
      name = $1
      if (name ~ /^__anon/) { sub(/.*::/, "", scope); name = "lambda in " scope }
      printf "%d\t%s:%d %s %d lines\n", n, $2, start, name, n
    }
    END { printf "0\tchecked %d\n", checked }')

checked=$(grep -P '^0\tchecked ' <<<"$out" | cut -d' ' -f2)
offenders=$(grep -vP '^0\tchecked ' <<<"$out" | sort -t$'\t' -k1,1nr -k2,2 | cut -f2- || true)
if [[ -z $offenders ]]; then
  echo "check_function_length: all $checked functions in ${present[*]} are at most $limit lines"
  exit 0
fi
echo "$offenders"
echo "check_function_length: $(wc -l <<<"$offenders") of $checked functions are over $limit lines (in ${present[*]})"
exit 1
