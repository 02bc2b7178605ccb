# tests/binaryswap/lib.sh — what the sort-last graph scripts share (sourced):
# writing a graph of N peers and a display node, running it under
# `tessera run`, and comparing every frame the display wrote with the
# native render. The caller sets bin, out and frames and defines fail().

# sl_write_graph GRAPH FORM TRANSPORT OPTIONS APP_COMMAND SHARE...
#   FORM insitu: each application runs binaryswap itself;
#        servers: application -> pack -> a render server ending in binaryswap.
#   One application per SHARE, running APP_COMMAND --part SHARE.
#   OPTIONS: binaryswap's options as YAML flow entries ("" for none);
#   a SHARE written "K/N;ENTRIES" gives that peer ENTRIES instead.
sl_write_graph() {
  _graph=$1 _form=$2 _transport=$3 _options=$4 _app=$5
  shift 5
  {
    echo "version: 1"
    echo "window: {width: 96, height: 72}"
    echo "defaults: {transport: $_transport}"
    echo "nodes:"
    _i=0
    for _share in "$@"; do
      _peer_options=$_options
      case $_share in *";"*) _peer_options=${_share#*;} _share=${_share%%;*} ;; esac
      echo "  app$_i:"
      echo "    exec: $_app --part $_share"
      if [ "$_form" = insitu ]; then
        echo "    chain: [{binaryswap: {$_peer_options}}]"
        echo "    to: display"
      else
        echo "    chain: [pack]"
        echo "    to: peer$_i"
        echo "  peer$_i:"
        echo "    chain: [{binaryswap: {$_peer_options}}]"
        echo "    to: display"
      fi
      _i=$((_i + 1))
    done
    echo "  display:"
    echo "    chain:"
    # SL_OUTPUT_ALPHA=true: the display's PNGs keep the composite's alpha
    echo "      - render: {output: \"out/f-%04d.png\", output_alpha: ${SL_OUTPUT_ALPHA:-false}}"
  } >"$_graph"
}

# sl_run GRAPH LOG_LEVEL: runs it into $out/run (stdout and stderr in
# $out/run.out, $out/run.err); sets rc, and fails (printing the end of the
# log) when the run did not exit 0.
sl_run() {
  TESSERA_LOG=$2 timeout 120 "$bin/tessera" run "$1" --out "$out/run" --no-progress >"$out/run.out" 2>"$out/run.err"
  rc=$?
}

sl_check_run() {
  [ $rc = 0 ] || { fail "tessera run exited $rc"; cat "$out/run.out"; tail -n 30 "$out/run.err"; }
}

# sl_compare_frames: frames 0..frames-1 of $out/run/out against $out/native,
# 0 differing pixels each.
sl_compare_frames() {
  _f=0
  while [ $_f -lt "$frames" ]; do
    _name=$(printf 'f-%04d.png' $_f)
    _diff=$("$bin/tessera" imgdiff "$out/native/$_name" "$out/run/out/$_name" 2>&1 | head -n 1)
    echo "frame $_f: $_diff"
    [ "$_diff" = "differing_pixels: 0" ] || fail "frame $_f differs from the native render ($_diff)"
    _f=$((_f + 1))
  done
}
