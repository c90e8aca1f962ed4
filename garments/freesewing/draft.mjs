// Drafts FreeSewing designs for catwalk's catalogue (see designs.json and
// docs/garment-format.md, "FreeSewing"). Usage: node draft.mjs [--out DIR] [id ...]
// Writes drafts/<id>.json: per size, the measurements used and every visible part's seam line
// (FreeSewing's `seam` path: millimetres, +y down) as simple ops, with its cut list entry.
import { readFileSync, writeFileSync, mkdirSync, renameSync } from 'node:fs'
import { dirname, join } from 'node:path'
import { fileURLToPath } from 'node:url'
import * as models from '@freesewing/models'
import { Teagan } from '@freesewing/teagan'
import { Penelope } from '@freesewing/penelope'
import { Titan } from '@freesewing/titan'
import { Bella } from '@freesewing/bella'
import { Simon } from '@freesewing/simon'

const DESIGNS = { teagan: Teagan, penelope: Penelope, titan: Titan, bella: Bella, simon: Simon }
const VERSION = '4.10.2'
const here = dirname(fileURLToPath(import.meta.url))
const config = JSON.parse(readFileSync(join(here, 'designs.json'), 'utf8'))
const recipes = JSON.parse(readFileSync(join(here, config.recipes), 'utf8')).bodies
// lengths (and the biceps and bust span) measured on our sample bodies
// (`catwalk garment freesewing-lengths`), in place of the model set's: they win over the scaling below
const lengths = config.lengths
  ? JSON.parse(readFileSync(join(here, config.lengths), 'utf8')).bodies
  : {}

// girths that follow chest, waist and seat when a model set is fitted to a recipe
const WITH_CHEST = ['highBust', 'underbust', 'bustFront', 'highBustFront', 'biceps', 'neck']
const WITH_WAIST = ['waistBack']
const WITH_SEAT = ['hips', 'seatBack', 'upperLeg']

function measurementsFor(sex, size) {
  const recipe = recipes.find((r) => r.name === `${sex}-${size}`)
  if (!recipe) throw new Error(`no recipe ${sex}-${size} in ${config.recipes}`)
  const group = sex === 'female' ? 'cisFemaleAdult' : 'cisMaleAdult'
  let best = null
  for (const s of models.sizes[group]) {
    const m = models[`${group}${s}`]
    if (!best || Math.abs(m.chest - recipe.bust * 1000) < Math.abs(best.m.chest - recipe.bust * 1000))
      best = { s, m }
  }
  const m = { ...best.m }
  const k = { chest: (recipe.bust * 1000) / m.chest, waist: (recipe.waist * 1000) / m.waist,
              seat: (recipe.hips * 1000) / m.seat }
  m.chest = recipe.bust * 1000
  m.waist = recipe.waist * 1000
  m.seat = recipe.hips * 1000
  for (const n of WITH_CHEST) if (n in m) m[n] *= k.chest
  for (const n of WITH_WAIST) if (n in m) m[n] *= k.waist
  for (const n of WITH_SEAT) if (n in m) m[n] *= k.seat
  const own = lengths[recipe.name] ?? {}
  for (const [n, v] of Object.entries(own)) m[n] = v
  for (const n of Object.keys(m)) m[n] = Math.round(m[n] * 10) / 10
  return { model: `${group}${best.s}`, recipe: recipe.name, measurements: m,
           lengthsFromBody: Object.keys(own) }
}

const r3 = (v) => Math.round(v * 1000) / 1000

function ops(path) {
  return path.ops.map((o) => {
    if (o.type === 'move') return ['M', r3(o.to.x), r3(o.to.y)]
    if (o.type === 'line') return ['L', r3(o.to.x), r3(o.to.y)]
    if (o.type === 'curve')
      return ['C', r3(o.cp1.x), r3(o.cp1.y), r3(o.cp2.x), r3(o.cp2.y), r3(o.to.x), r3(o.to.y)]
    if (o.type === 'close') return ['Z']
    throw new Error(`unknown path op ${o.type}`)
  })
}

function draft(g) {
  const Design = DESIGNS[g.design]
  if (!Design) throw new Error(`unknown design ${g.design}`)
  const out = { id: g.id, design: g.design, version: VERSION, options: g.options, units: 'mm',
                axes: 'FreeSewing: +x right, +y down', licence: 'FreeSewing designs: MIT',
                sizes: {} }
  for (const size of g.sizes) {
    const fit = measurementsFor(g.sex, size)
    const pattern = new Design({ measurements: fit.measurements, options: g.options, sa: 0,
                                 complete: false, paperless: false })
    pattern.draft()
    const store = pattern.setStores[0]
    const errors = store.logs?.error ?? []
    if (errors.length) throw new Error(`${g.id} ${size}: ${JSON.stringify(errors)}`)
    const parts = {}
    for (const [name, part] of Object.entries(pattern.parts[0])) {
      if (part.hidden || !part.paths.seam) continue
      const cut = store.cutlist?.[name]?.materials?.fabric?.[0] ?? { cut: 1, onFold: false }
      parts[name] = { seam: ops(part.paths.seam), cut: cut.cut, onFold: !!cut.onFold }
    }
    out.sizes[size] = { ...fit, parts }
  }
  return out
}

const args = process.argv.slice(2)
let outDir = join(here, 'drafts')
const at = args.indexOf('--out')
if (at >= 0) {
  outDir = args[at + 1]
  args.splice(at, 2)
}
const only = args
mkdirSync(outDir, { recursive: true })
for (const g of config.garments) {
  if (only.length && !only.includes(g.id)) continue
  const res = draft(g)
  const file = join(outDir, `${g.id}.json`)
  writeFileSync(`${file}.tmp`, JSON.stringify(res, null, 1) + '\n')
  renameSync(`${file}.tmp`, file)
  const counts = Object.entries(res.sizes).map(([s, v]) => `${s}: ${Object.keys(v.parts).length} parts`)
  console.log(`${g.id} (${g.design}): ${counts.join(', ')} -> ${file}`)
}
