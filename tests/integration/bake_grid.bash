# tests/integration/bake_grid.bash — grid N Z: an N x N grid OBJ over [0,1]² on stdout with
# uv = xy (one chart, no overlap) and z = Z 16 x (1 - x) y (1 - y) (a hill), for the bakes of
# bake.sh and gltf_validator.sh through a result's own texture coordinates.
grid() {
  local n=$1 z=$2 i j a b c d
  for ((j = 0; j < n; j++)); do
    for ((i = 0; i < n; i++)); do
      awk -v i="$i" -v j="$j" -v n="$n" -v z="$z" 'BEGIN { x = i / (n - 1); y = j / (n - 1);
        printf "v %.6f %.6f %.6f\nvt %.6f %.6f\n", x, y, z * 16 * x * (1 - x) * y * (1 - y), x, y }'
    done
  done
  for ((j = 0; j + 1 < n; j++)); do
    for ((i = 0; i + 1 < n; i++)); do
      a=$((j * n + i + 1)) b=$((j * n + i + 2)) c=$((j * n + i + 1 + n)) d=$((j * n + i + 2 + n))
      echo "f $a/$a $b/$b $d/$d"
      echo "f $a/$a $d/$d $c/$c"
    done
  done
}
