complete -c pat-tile -s o -l output -d 'Output file; `-` is standard output (binary output to a terminal is refused)' -r
complete -c pat-tile -l size -d 'Image size (WxH); default 1024x768. With --pat the new pattern\'s size, NxN (square, a multiple of 16 up to 4096), which --pat needs: the default is not square' -r
complete -c pat-tile -l scale -d 'Each texel becomes an N x N block of pixels' -r
complete -c pat-tile -l offset -d 'The texel shown at the lower-left pixel (COL,ROW); negative values allowed' -r
complete -c pat-tile -l background -d 'Colour for transparent texels (`r,g,b` or `#rrggbb`). Without it, PNG and PAM keep transparency as alpha and PPM shows black with a warning' -r
complete -c pat-tile -l format -d 'Image format; by default from the output\'s extension, PNG on standard output. Always 8-bit sRGB: a pattern\'s colours are 8-bit codes, which more bits or PFM\'s floats would only repeat' -r -f -a "png\t'PNG, lossless, with alpha when the image has transparency'
ppm\t'Binary PPM (P6); transparency is flattened'
pam\t'PAM (P7), RGB or RGB_ALPHA'"
complete -c pat-tile -l pat -d 'Write a tiled .pat of --size instead of an image'
complete -c pat-tile -s h -l help -d 'Print help (see more with \'--help\')'
complete -c pat-tile -s V -l version -d 'Print version'
