// Reads a .pmtiles archive with the reference JavaScript reader (npm
// `pmtiles`), for the C++ tests: node pmtiles_read.mjs ARCHIVE IDS OUTDIR.
// IDS holds "z x y" lines; each tile found is written to OUTDIR/z_x_y.bin.
// Prints the header and metadata as JSON, then "missing z x y" lines.
import fs from 'node:fs/promises';
import path from 'node:path';
import {PMTiles} from 'pmtiles';

// A pmtiles Source over a local file (the package's own sources are for
// fetch and browser File objects).
class LocalFile {
  constructor(file) {
    this.file = file;
  }
  getKey() {
    return this.file;
  }
  async getBytes(offset, length) {
    const handle = await fs.open(this.file, 'r');
    try {
      const buffer = Buffer.alloc(length);
      const {bytesRead} = await handle.read(buffer, 0, length, offset);
      const data = buffer.buffer.slice(buffer.byteOffset, buffer.byteOffset + bytesRead);
      return {data};
    } finally {
      await handle.close();
    }
  }
}

const [archive, idsFile, outDir] = process.argv.slice(2);
const pm = new PMTiles(new LocalFile(archive));
const header = await pm.getHeader();
const metadata = await pm.getMetadata();
console.log(JSON.stringify({header, metadata}));
await fs.mkdir(outDir, {recursive: true});
const lines = (await fs.readFile(idsFile, 'utf8')).split('\n').filter(l => l.trim());
for (const line of lines) {
  const [z, x, y] = line.trim().split(/\s+/).map(Number);
  const tile = await pm.getZxy(z, x, y);
  if (!tile) {
    console.log(`missing ${z} ${x} ${y}`);
    continue;
  }
  await fs.writeFile(path.join(outDir, `${z}_${x}_${y}.bin`), Buffer.from(tile.data));
}
