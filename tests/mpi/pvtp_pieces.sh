# Sourced by the mpi render tests: write_pvtp TUBECAST SCENE PVTP SEED... [-- CONVERT_OPTIONS...]
# converts SCENE's generated tornado once per seed (--set dataset.seed=SEED plus CONVERT_OPTIONS)
# to pieceSEED.vtp and writes PVTP, a ParaView partitioned file of those pieces in seed order.
# Returns 1 (stderr in ./err) when a conversion fails.
write_pvtp() {
    local tubecast=$1 scene=$2 pvtp=$3
    shift 3
    local seeds=() options=()
    while [[ $# -gt 0 && $1 != -- ]]; do seeds+=("$1"); shift; done
    [[ $# -gt 0 ]] && shift
    options=("$@")
    local seed
    for seed in "${seeds[@]}"; do
        "$tubecast" convert "$scene" "piece$seed.vtp" --set "dataset.seed=$seed" "${options[@]}" 2>err >/dev/null ||
            return 1
    done
    {
        cat <<'EOF'
<?xml version="1.0"?>
<VTKFile type="PPolyData" version="1.0" byte_order="LittleEndian" header_type="UInt64">
  <PPolyData GhostLevel="0">
    <PPointData>
      <PDataArray type="Float32" Name="speed"/>
      <PDataArray type="Float32" Name="height"/>
      <PDataArray type="Float32" Name="arc_length"/>
    </PPointData>
    <PPoints><PDataArray type="Float32" Name="Points" NumberOfComponents="3"/></PPoints>
EOF
        for seed in "${seeds[@]}"; do echo "    <Piece Source=\"piece$seed.vtp\"/>"; done
        echo "  </PPolyData>"
        echo "</VTKFile>"
    } >"$pvtp"
}
