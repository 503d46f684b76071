complete -c pat-info -l record -d 'Print record N of the polygon stream FILE: its stripe texture in the seed\'s terms (spacing, start point, yaw, pitch, translation, colour select and colour code). Records are numbered from 0 in the order of the stream, every element counting (object definitions and instances too): the numbers error messages give. For an object definition (drawn untransformed) or an instance, every polygon it draws that has a stripe is shown, as `record N, polygon K` (K from 0 in drawing order), each an element of --json\'s "records"' -r
complete -c pat-info -l at -d 'Also show the texel at column COL, row ROW (row 0 is the bottom row)' -r
complete -c pat-info -l color -d 'When the preview uses colour: `auto` when standard output is a terminal and NO_COLOR is unset or empty (<https://no-color.org>), `always` (even into a pipe, whatever NO_COLOR says), or `never`' -r -f -a "auto\t'When standard output is a terminal and NO_COLOR is unset or empty'
always\t'Always, even into a pipe and whatever NO_COLOR says'
never\t'Never'"
complete -c pat-info -l preview-size -d 'Widest preview in texels; larger patterns are shown subsampled' -r
complete -c pat-info -l check -d 'Validate only: print nothing on success, one error per invalid file, and exit 1 if any file is invalid'
complete -c pat-info -l json -d 'Print one JSON object instead of text: {"version": 1, "tool": "pat-info", "files": [...]} with an object per file, or with --record "records": [...] (docs/json.md)'
complete -c pat-info -l preview -d 'Draw the pattern in the terminal with 24-bit colour, two texels per character cell; transparent texels show as a grey checker. Without colour (--color), one character per texel names its colour as the table numbers them (1-9, A-Z, a-z; `?` beyond 61, `.` transparent), with a legend'
complete -c pat-info -s h -l help -d 'Print help (see more with \'--help\')'
complete -c pat-info -s V -l version -d 'Print version'
