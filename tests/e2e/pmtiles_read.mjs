// Reads a .pmtiles archive with the reference JavaScript reader (npm
// `pmtiles`), for the C++ tests: node pmtiles_read.mjs ARCHIVE IDS OUT.
// IDS holds "z x y" lines. Prints the header and metadata as JSON, then per
// id "tile z x y LENGTH" (its bytes appended to the file OUT, in id order)
// or "missing z x y".
import fs from 'node:fs/promises';
import path from 'node:path';
import {PMTiles} from 'pmtiles';

// A pmtiles Source over a local file (the package's own sources are for
// fetch and browser File objects).
class LocalFile {
  constructor(file) {
    this.file = file;
    this.handle = fs.open(file, 'r');
  }
  getKey() {
    return this.file;
  }
  async getBytes(offset, length) {
    const buffer = Buffer.alloc(length);
    const {bytesRead} = await (await this.handle).read(buffer, 0, length, offset);
    return {data: buffer.buffer.slice(buffer.byteOffset, buffer.byteOffset + bytesRead)};
  }
}

const [archive, idsFile, outFile] = process.argv.slice(2);
const pm = new PMTiles(new LocalFile(archive));
const header = await pm.getHeader();
const metadata = await pm.getMetadata();
console.log(JSON.stringify({header, metadata}));
const lines = (await fs.readFile(idsFile, 'utf8')).split('\n').filter(l => l.trim());
const report = [];
const blobs = [];
for (const line of lines) {
  const [z, x, y] = line.trim().split(/\s+/).map(Number);
  const tile = await pm.getZxy(z, x, y);
  if (!tile) {
    report.push(`missing ${z} ${x} ${y}`);
    continue;
  }
  blobs.push(Buffer.from(tile.data));
  report.push(`tile ${z} ${x} ${y} ${tile.data.byteLength}`);
}
await fs.writeFile(outFile, Buffer.concat(blobs));
console.log(report.join('\n'));
