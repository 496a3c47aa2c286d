# Sourced by the bench's shell tests (sh): whether a command failed as it should.
#   check_failure WHAT EXPECTED_CODE EXPECTED_TEXT CODE MESSAGE
# Returns 0 when CODE is EXPECTED_CODE and MESSAGE contains EXPECTED_TEXT; else says which differs
# (WHAT names the case) on standard error and returns 1.
check_failure() {
  if [ "$4" -ne "$2" ]; then
    echo "$1: expected exit code $2, got $4" >&2
    return 1
  fi
  case "$5" in
    *"$3"*) return 0 ;;
  esac
  echo "$1: expected a message containing \"$3\", got: $5" >&2
  return 1
}
