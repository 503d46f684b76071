complete -c pat-from-image -s o -l output -d 'Output .pat file; `-` is standard output. Written only if the whole conversion succeeds' -r
complete -c pat-from-image -l size -d 'Side of the pattern in texels (`N` or `NxN`): a multiple of 16 from 16 to 4096' -r
complete -c pat-from-image -l colors -d 'Number of colours to choose, 1 to 256. An image of this many distinct colours or fewer keeps exactly its colours if it is not resampled (its centred square, or the `--crop`, is already SIZE pixels a side); resampling blends colours' -r
complete -c pat-from-image -l dither -d 'How pixels take palette colours. `none` (the default) keeps texels crisp and tiles seamlessly, which suits texture patterns best; `floyd-steinberg` diffuses the error (in linear light) for smooth gradients; `ordered` uses an 8x8 Bayer matrix, whose regular texture also tiles' -r -f -a "none\t'Each pixel takes its nearest palette colour: crisp texels, best PSNR'
floyd-steinberg\t'Error diffusion in linear light, serpentine scan'
ordered\t'8x8 Bayer threshold matrix: a regular texture that tiles cleanly'"
complete -c pat-from-image -l palette -d 'Use these colours instead of choosing them: a .pat file (its palette, in its order) or a text file with one colour per line as `r,g,b` or `#rrggbb` (a `#` not followed by a hex digit starts a comment). At most 256 colours' -r
complete -c pat-from-image -l alpha-threshold -d 'Pixels whose alpha (0-255) is below this become transparent texels; 0 keeps every pixel' -r
complete -c pat-from-image -l transparent -d 'Pixels of exactly this colour (`r,g,b` or `#rrggbb`, after resampling) become transparent texels too. Default: none' -r
complete -c pat-from-image -l angle -d 'With --stripe: the direction across the stripes, degrees counter-clockwise from the image\'s +x axis (0: the map runs left to right; 90: bottom to top)' -r
complete -c pat-from-image -l length -d 'With --stripe: the map\'s length, a power of two from 1 to 65536' -r
complete -c pat-from-image -l threads -d 'Worker threads (default: all cores). The output is identical for any N' -r
complete -c pat-from-image -l crop -d 'Take the central N x N pixels of the image as they are, without resampling. The image must be at least N x N'
complete -c pat-from-image -l report -d 'Print the pattern\'s size, colours and PSNR against the resampled image (8-bit sRGB, over coloured texels) to standard error'
complete -c pat-from-image -l stripe -d 'Write a stripe modulation map instead of a pattern: the image\'s luminance (linear light, alpha-weighted) averaged along the stripes, its profile across them resampled to --length entries and encoded to 0..=255 sRGB'
complete -c pat-from-image -l no-progress -d 'Show no progress bar. Bars are drawn on standard error only when it is a terminal (and TERM is not "dumb"), never into a pipe or a file, and cleared when the job ends'
complete -c pat-from-image -s h -l help -d 'Print help (see more with \'--help\')'
complete -c pat-from-image -s V -l version -d 'Print version'
