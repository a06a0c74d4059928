# Sourced by the scripts that download from Debian (fetch-meshlab-sources.sh, make-meshlab-root.sh):
# the mirror this machine's apt already uses, so no other host is named.
# The machine's own Debian mirror (deb822 .sources first, then one-line sources.list), skipping
# the security archive, whose pool has no meshlab.
machine_mirror() {
  local uri=""
  if compgen -G "/etc/apt/sources.list.d/*.sources" >/dev/null; then
    uri=$(awk 'tolower($1) == "uris:" { for (i = 2; i <= NF; i++) print $i }' \
      /etc/apt/sources.list.d/*.sources | grep -v -- '-security' | head -n1 || true)
  fi
  if [[ -z "$uri" && -r /etc/apt/sources.list ]]; then
    uri=$(awk '$1 == "deb" { for (i = 2; i <= NF; i++) if ($i ~ /^[a-z+]+:\/\//) { print $i; break } }' \
      /etc/apt/sources.list | grep -v -- '-security' | head -n1 || true)
  fi
  echo "${uri%/}"
}
